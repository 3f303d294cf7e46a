"""Build ``dist/PipePlug.fmu``: the pythonfmu slave, the ``pipeplug`` core and the documentation.

Usage (from the repository root, inside the project's environment)::

    python build_fmu.py                    # writes dist/PipePlug.fmu
    python build_fmu.py --dest out/X.fmu   # another destination

The FMU's resources hold the slave ``fmu_src/PipePlug.py``, its interface module
``fmu_src/pipeplug_fmi.py`` and the core package ``fmu_src/pipeplug`` (without
``__pycache__``), so the FMU runs in any Python-hosted FMI importer that has numpy, without this
repository. ``documentation/index.html`` is generated from the same tables the FMU registers
its variables from, so the two cannot disagree.
"""
from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent
SOURCES = ROOT / "fmu_src"
SLAVE = SOURCES / "PipePlug.py"
SHIPPED = (SOURCES / "pipeplug_fmi.py", SOURCES / "pythonfmu_exit_guard.py", SOURCES / "pipeplug")
DEFAULT_DEST = ROOT / "dist" / "PipePlug.fmu"


def build(dest: Path = DEFAULT_DEST) -> Path:
    """Build the FMU at ``dest`` and return its path."""
    from pythonfmu import FmuBuilder

    sys.path.insert(0, str(SOURCES))
    from fmu_documentation import documentation_html

    dest = Path(dest).resolve()
    dest.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="pipeplug_build_") as tmp:
        staged = [_stage(path, Path(tmp) / "resources") for path in SHIPPED]
        docs = Path(tmp) / "documentation"
        docs.mkdir()
        (docs / "index.html").write_text(documentation_html(), encoding="utf-8")
        return Path(FmuBuilder.build_FMU(
            SLAVE, dest=dest, project_files=staged, documentation_folder=docs,
            canGetAndSetFMUstate=True, canSerializeFMUstate=True,
            canHandleVariableCommunicationStepSize=True, needsExecutionTool=True))


def _stage(path: Path, folder: Path) -> Path:
    """Copy a file or package into ``folder``, leaving compiled caches behind."""
    folder.mkdir(exist_ok=True)
    target = folder / path.name
    if path.is_dir():
        shutil.copytree(path, target, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    else:
        shutil.copy2(path, target)
    return target


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dest", type=Path, default=DEFAULT_DEST,
                        help="where to write the FMU (default: dist/PipePlug.fmu)")
    print(build(parser.parse_args(argv).dest))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
