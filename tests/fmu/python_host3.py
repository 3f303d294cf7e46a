"""The plain C FMI 3.0 host's commands (``fmi3_host.c``) inside a Python process.

    python python_host3.py HOST_LIBRARY BINARY < commands

``fmi3_host.c`` compiled as a library (``-DPYTHON_HOST``) runs its loop called through ctypes,
as FMPy calls an FMU's functions: the FMU finds this process's interpreter and runs in it, with
the same commands and answers as the C host (:class:`~fmi_c_host.CHost` drives both).
"""
import ctypes
import sys

if __name__ == "__main__":
    host = ctypes.CDLL(sys.argv[1])
    host.host_main.argtypes = [ctypes.c_char_p]
    sys.exit(host.host_main(sys.argv[2].encode()))
