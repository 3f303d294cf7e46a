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
import zipfile
from pathlib import Path
from xml.etree import ElementTree

__all__ = ["INNER_NAME", "SOURCES", "TARGET", "compile_loader", "inner_name", "model_token",
           "platform_folder"]

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
_TOKEN = re.compile(r"\{?[0-9a-fA-F]{8}(-[0-9a-fA-F]{4}){3}-[0-9a-fA-F]{12}\}?")  # a UUID, braced or not


def inner_name(model_identifier: str) -> str:
    """The file name of pythonfmu's binary beside the loader (``loader.c``: INNER_BINARY)."""
    return f"{model_identifier}_pythonfmu.so"


INNER_NAME = inner_name("PipePlug")        # PipePlug.fmu's


def platform_folder(version: int) -> str:
    """The FMU's folder of linux64 binaries in FMI ``version`` (2 or 3)."""
    return "binaries/x86_64-linux" if version == 3 else "binaries/linux64"


def compile_loader(dest: Path, model_identifier: str, version: int, token: str) -> Path:
    """Compile the FMI ``version`` (2 or 3) loader for the FMU ``model_identifier`` into the
    shared library ``dest``; it instantiates for the ``token`` alone (the guid or
    instantiationToken of the FMU's modelDescription.xml, :func:`model_token`).

    Returns ``dest``. Raises ValueError for an identifier that is not a C identifier or a token
    that is not a UUID, and RuntimeError with the compiler's messages when compiling
    fails.
    """
    if not _IDENTIFIER.fullmatch(model_identifier):
        raise ValueError(f"model identifier {model_identifier!r} is not a C identifier")
    if not _TOKEN.fullmatch(token):
        raise ValueError(f"token {token!r} is not a UUID")
    if version not in SOURCES:
        raise ValueError(f"FMI version {version!r} is not allowed; allowed: 2, 3")
    cmd = [sys.executable, "-m", "ziglang", "cc", *_FLAGS, f"-DMODEL_IDENTIFIER={model_identifier}",
           f"-DFMI_VERSION={version}", f'-DTOKEN="{token}"', "-target", TARGET, "-o", str(dest),
           *map(str, SOURCES[version])]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"compiling the FMU's loader failed ({' '.join(cmd)}):\n"
                           f"{proc.stdout}{proc.stderr}")
    return dest


def model_token(fmu: Path, version: int) -> str:
    """The guid (FMI 2.0) or instantiationToken (FMI 3.0) of the FMU ``fmu``'s
    modelDescription.xml."""
    with zipfile.ZipFile(fmu) as archive:
        root = ElementTree.fromstring(archive.read("modelDescription.xml"))
    return root.attrib["instantiationToken" if version == 3 else "guid"]
