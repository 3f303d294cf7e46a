"""Build ``PipePlug.fmu`` from the installed ``pipeplug`` core and this adapter (pythonfmu).

Usage (inside an environment with ``pipeplug[fmu]`` installed)::

    python -m pipeplug_fmu build                    # writes dist/PipePlug.fmu
    python -m pipeplug_fmu build --dest out/X.fmu   # another destination

(``python build_fmu.py`` in the repository does the same.)

The FMU's resources hold a script ``pipeplug_slave_<tag>.py`` and one package
``pipeplug_fmu_<tag>``: the adapter's run-time modules (:mod:`~pipeplug_fmu.slave`,
:mod:`~pipeplug_fmu.fmi`) with the core beside them as ``pipeplug_fmu_<tag>.pipeplug``.
``<tag>`` is a digest of the content of everything shipped: pythonfmu runs all FMUs of a process
in one interpreter and imports their modules by name, so a rebuilt FMU with a changed core gets
names of its own and never runs another build's code, while two copies of the same build share
modules that are identical anyway. The FMU needs nothing from
this repository; ``documentation/index.html`` is generated from the same tables the FMU registers
its variables from, so the two cannot disagree.

pythonfmu writes the zip with its own binaries; the build then compiles the loader
(:mod:`pipeplug_fmu.native`, with the ``ziglang`` package) and puts it at
``binaries/linux64/PipePlug.so``, pythonfmu's linux64 binary beside it as
``PipePlug_pythonfmu.so``. The win64 binary is pythonfmu's, unchanged.
"""
from __future__ import annotations

import argparse
import hashlib
import shutil
import sys
import tempfile
import zipfile
from pathlib import Path

from .native import INNER_NAME, compile_loader

__all__ = ["build", "stage", "install_loader", "main", "DEFAULT_DEST"]

DEFAULT_DEST = Path("dist") / "PipePlug.fmu"
_ADAPTER = Path(__file__).resolve().parent
_RUNTIME = ("__init__.py", "slave.py", "fmi.py")   # shipped adapter modules
_TAG_LENGTH = 12
_LINUX_BINARY = "binaries/linux64/PipePlug.so"


def build(dest: Path = DEFAULT_DEST) -> Path:
    """Build the FMU at ``dest`` and return its path."""
    from pythonfmu import FmuBuilder

    from .documentation import documentation_html

    dest = Path(dest).resolve()
    dest.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="pipeplug_build_") as tmp:
        script, package = stage(Path(tmp) / "stage")
        docs = Path(tmp) / "documentation"
        docs.mkdir()
        (docs / "index.html").write_text(documentation_html(), encoding="utf-8")
        fmu = Path(FmuBuilder.build_FMU(
            script, dest=dest, project_files=[package], documentation_folder=docs,
            canGetAndSetFMUstate=True, canSerializeFMUstate=True,
            canHandleVariableCommunicationStepSize=True, needsExecutionTool=True))
        install_loader(fmu, compile_loader(Path(tmp) / "PipePlug.so"))
        return fmu


def install_loader(fmu: Path, loader: Path) -> None:
    """Rewrite the zip ``fmu``: the loader becomes binaries/linux64/PipePlug.so, pythonfmu's
    binary moves beside it as :data:`~pipeplug_fmu.native.INNER_NAME`; all else is copied."""
    inner = f"{_LINUX_BINARY.rsplit('/', 1)[0]}/{INNER_NAME}"
    rewritten = fmu.with_suffix(".rewriting")
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(rewritten, "w") as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename == _LINUX_BINARY:
                dst.writestr(_renamed(info, inner), data)
                data = loader.read_bytes()
            dst.writestr(info, data)
    rewritten.replace(fmu)


def _renamed(info: zipfile.ZipInfo, name: str) -> zipfile.ZipInfo:
    """A copy of ``info`` (date, permissions, compression) under another ``name``."""
    copy = zipfile.ZipInfo(name, info.date_time)
    copy.compress_type, copy.external_attr = info.compress_type, info.external_attr
    return copy


def stage(folder: Path) -> tuple[Path, Path]:
    """Write the slave script and its package into ``folder``; return both paths.

    The package is the adapter's run-time modules plus the core, both without compiled caches;
    its name and the script's carry the digest of their content.
    """
    import pipeplug

    core = Path(pipeplug.__file__).resolve().parent
    files = [(name, _ADAPTER / name) for name in _RUNTIME]
    files += [(f"pipeplug/{p.relative_to(core).as_posix()}", p) for p in sorted(core.rglob("*.py"))]
    digest = hashlib.sha256()
    for relative, path in files:
        digest.update(relative.encode() + b"\0" + path.read_bytes() + b"\0")
    tag = digest.hexdigest()[:_TAG_LENGTH]
    package = folder / f"pipeplug_fmu_{tag}"
    for relative, path in files:
        target = package / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(path, target)
    script = folder / f"pipeplug_slave_{tag}.py"
    script.write_text(_SCRIPT.format(tag=tag), encoding="utf-8")
    return script, package


# pythonfmu 0.7's fmi2Instantiate imports the slave script's module, executes the file once
# more with the module's namespace as globals and a fresh dict as locals (to find the class),
# and then releases that namespace, which it had only borrowed. Each instantiation would leave
# the namespace one reference short, until it is freed under the module. The script takes the
# reference back in exactly that execution, the one whose locals are not its globals.
_SCRIPT = '''"""The PipePlug slave of build {tag} (see pipeplug_fmu.build)."""
import ctypes as _ctypes

from pipeplug_fmu_{tag}.slave import PipePlug

__all__ = ["PipePlug"]

if locals() is not globals():   # pythonfmu's class search: it releases globals() once after
    _ctypes.pythonapi.Py_IncRef(_ctypes.py_object(globals()))
'''


def main(argv: list[str] | None = None) -> int:
    """Command line: ``[build] [--dest PATH]``."""
    parser = argparse.ArgumentParser(prog="python -m pipeplug_fmu",
                                     description="Build dist/PipePlug.fmu.")
    parser.add_argument("command", nargs="?", choices=("build",), default="build",
                        help="what to do (only: build)")
    parser.add_argument("--dest", type=Path, default=DEFAULT_DEST,
                        help=f"where to write the FMU (default: {DEFAULT_DEST})")
    print(build(parser.parse_args(argv).dest))
    return 0


if __name__ == "__main__":
    sys.exit(main())
