"""The FMUs' linux64 binary: a small loader in front of pythonfmu's (see ``loader.c``; the other
sources are its parts: ``python.c`` finds a Python, ``inner.c`` loads pythonfmu's binary and
guards its exit, ``resources.c`` checks the resource folder, ``states.c`` the FMU states,
``text.c`` holds text helpers).

It is compiled at build time, once per FMU with its model identifier as a compile-time define,
with the C compiler of the ``ziglang`` package (``python -m ziglang cc``), for the oldest glibc
it needs, so the FMU runs on older Linux systems than the one that built it. pythonfmu's own
binary is shipped beside it under :func:`inner_name`.
"""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

__all__ = ["INNER_NAME", "SOURCES", "TARGET", "compile_loader", "inner_name"]

SOURCES = tuple(sorted(Path(__file__).resolve().parent.glob("*.c")))   # with loader.h
TARGET = "x86_64-linux-gnu.2.17"           # zig target: x86-64 Linux, glibc >= 2.17
# nodelete: the loader stays mapped after a host unloads it, like pythonfmu's binary (which
# glibc never unloads), so the exit handler it registers stays valid until the process exits.
_FLAGS = ("-shared", "-fPIC", "-O2", "-fvisibility=hidden", "-Wall", "-Wextra", "-Werror",
          "-Wl,-z,nodelete")
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")   # a C identifier (FMI's modelIdentifier)


def inner_name(model_identifier: str) -> str:
    """The file name of pythonfmu's binary beside the loader (``loader.c``: INNER_BINARY)."""
    return f"{model_identifier}_pythonfmu.so"


INNER_NAME = inner_name("PipePlug")        # PipePlug.fmu's


def compile_loader(dest: Path, model_identifier: str = "PipePlug") -> Path:
    """Compile the loader's sources for the FMU ``model_identifier`` into the shared library ``dest``.

    Returns ``dest``. Raises ValueError for an identifier that is not a C identifier, and
    RuntimeError with the compiler's messages when compiling fails.
    """
    if not _IDENTIFIER.fullmatch(model_identifier):
        raise ValueError(f"model identifier {model_identifier!r} is not a C identifier")
    cmd = [sys.executable, "-m", "ziglang", "cc", *_FLAGS, f"-DMODEL_IDENTIFIER={model_identifier}",
           "-target", TARGET, "-o", str(dest), *map(str, SOURCES)]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"compiling the FMU's loader failed ({' '.join(cmd)}):\n"
                           f"{proc.stdout}{proc.stderr}")
    return dest
