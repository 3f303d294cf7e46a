"""The loader's exit guard finds pythonfmu's interpreter state in a Python host, and Python hosts
exit cleanly after FMU runs (the C host's case is in ``test_fmu_c_host.py``)."""
import subprocess
import sys
import textwrap

PROBE = textwrap.dedent("""
    import ctypes, shutil, sys, tempfile
    from pathlib import Path
    import numpy as np
    from fmpy import extract, simulate_fmu
    folder = Path(extract(sys.argv[1], tempfile.mkdtemp()))
    loader = folder / "binaries" / "linux64" / "PipePlug.so"
    signal = np.array([(0.0, 23e3), (0.05, 23e3), (0.05, 0.0), (0.06, 0.0)],
                      dtype=[("time", float), ("Q", float)])
    simulate_fmu(str(folder), stop_time=0.06, output_interval=1e-3, input=signal,
                 start_values={"elastic": True, "dx": 0.05}, output=["v_pipe"])
    target = ctypes.CDLL(str(loader)).PipePlug_exitGuardTarget   # the loader fmpy loaded
    target.restype = ctypes.c_void_p
    address = target()
    inner = []                                  # where pythonfmu's binary is mapped
    for line in open("/proc/self/maps"):
        if line.rstrip().endswith("/binaries/linux64/PipePlug_pythonfmu.so"):
            inner.append([int(x, 16) for x in line.split()[0].split("-")])
    inside = any(lo <= address < hi for lo, hi in inner)
    words = (ctypes.c_uint64 * 2).from_address(address) if address else (0, 0)
    # a live shared_ptr: two non-null, aligned heap addresses
    live = all(w and w % 8 == 0 for w in words)
    shutil.rmtree(folder)                       # the binaries' files are gone at exit
    print("ARMED" if inside and live else f"NOT ARMED {address} {inner} {list(words)}")
""")


def test_guard_is_armed_on_the_shared_ptr_and_hosts_exit_cleanly(fmu_file, tmp_path):
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    # Without a guard about half of such runs (numba loaded, FMU folder deleted) aborted at exit
    # with "corrupted double-linked list".
    for _ in range(6):
        proc = subprocess.run([sys.executable, str(script), str(fmu_file)], capture_output=True,
                              text=True, timeout=300, check=False)
        assert proc.returncode == 0, proc.stderr[-2000:]
        assert "ARMED" in proc.stdout and "NOT ARMED" not in proc.stdout, proc.stdout
