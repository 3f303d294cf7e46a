"""The FMU's linux64 binary: a small loader in front of pythonfmu's (see ``loader.c``).

It is compiled at build time with the C compiler of the ``ziglang`` package
(``python -m ziglang cc``), for the oldest glibc it needs, so the FMU runs on older Linux
systems than the one that built it. pythonfmu's own binary is shipped beside it under
:data:`INNER_NAME`.
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

__all__ = ["INNER_NAME", "SOURCE", "TARGET", "compile_loader"]

SOURCE = Path(__file__).resolve().with_name("loader.c")
INNER_NAME = "PipePlug_pythonfmu.so"       # loader.c: INNER_BINARY
TARGET = "x86_64-linux-gnu.2.17"           # zig target: x86-64 Linux, glibc >= 2.17
# nodelete: the loader stays mapped after a host unloads it, like pythonfmu's binary (which
# glibc never unloads), so the exit handler it registers stays valid until the process exits.
_FLAGS = ("-shared", "-fPIC", "-O2", "-fvisibility=hidden", "-Wall", "-Wextra", "-Werror",
          "-Wl,-z,nodelete")


def compile_loader(dest: Path) -> Path:
    """Compile ``loader.c`` into the shared library ``dest``; return ``dest``.

    Raises RuntimeError with the compiler's messages when it fails.
    """
    cmd = [sys.executable, "-m", "ziglang", "cc", *_FLAGS, "-target", TARGET, "-o", str(dest),
           str(SOURCE)]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        raise RuntimeError(f"compiling the FMU's loader failed ({' '.join(cmd)}):\n"
                           f"{proc.stdout}{proc.stderr}")
    return dest
