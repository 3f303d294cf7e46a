"""The FMUs' linux64 binary: a small loader in front of pythonfmu's (FMI 2.0: ``loader.c`` with
``fmi2.h``) or pythonfmu3's (FMI 3.0: ``loader3.c`` with ``fmi3.h``). The other sources are
shared by both versions: ``calls.c`` checks every call and holds the calls both versions
have alike, ``log.c`` gives lines to the host, ``python.c`` finds a Python, ``inner.c`` loads
pythonfmu's binary and guards its exit, ``resources.c`` checks the resource folder,
``states.c`` the FMU states (and has their calls), ``text.c`` holds text helpers.

It is compiled at build time, once per FMU and FMI version with its model identifier and the
version as compile-time defines,
with the C compiler of the ``ziglang`` package (``python -m ziglang cc``), for the oldest glibc
it needs, so the FMU runs on older Linux systems than the one that built it. pythonfmu's own
binary is shipped beside it under :func:`inner_name`.
"""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

__all__ = ["INNER_NAME", "SOURCES", "TARGET", "compile_loader", "inner_name", "platform_folder"]

_HERE = Path(__file__).resolve().parent
_ENTRY = {2: _HERE / "loader.c", 3: _HERE / "loader3.c"}        # each version's FMI functions
#: The sources of each FMI version's loader (with loader.h and the version's header).
SOURCES = {version: tuple(sorted(p for p in _HERE.glob("*.c") if p not in _ENTRY.values()))
           + (entry,) for version, entry in _ENTRY.items()}
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


def platform_folder(version: int) -> str:
    """The FMU's folder of linux64 binaries in FMI ``version`` (2 or 3)."""
    return "binaries/x86_64-linux" if version == 3 else "binaries/linux64"


def compile_loader(dest: Path, model_identifier: str = "PipePlug", version: int = 2) -> Path:
    """Compile the FMI ``version`` (2 or 3) loader for the FMU ``model_identifier`` into the
    shared library ``dest``.

    Returns ``dest``. Raises ValueError for an identifier that is not a C identifier, and
    RuntimeError with the compiler's messages when compiling fails.
    """
    if not _IDENTIFIER.fullmatch(model_identifier):
        raise ValueError(f"model identifier {model_identifier!r} is not a C identifier")
    if version not in SOURCES:
        raise ValueError(f"FMI version {version!r} is not allowed; allowed: 2, 3")
    cmd = [sys.executable, "-m", "ziglang", "cc", *_FLAGS, f"-DMODEL_IDENTIFIER={model_identifier}",
           f"-DFMI_VERSION={version}", "-target", TARGET, "-o", str(dest),
           *map(str, SOURCES[version])]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"compiling the FMU's loader failed ({' '.join(cmd)}):\n"
                           f"{proc.stdout}{proc.stderr}")
    return dest
