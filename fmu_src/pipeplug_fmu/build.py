"""Build ``PipePlug.fmu``, ``Hammer.fmu`` and the pipe-ramming system files (pythonfmu).

Usage (inside an environment with ``pipeplug[fmu]`` installed)::

    python -m pipeplug_fmu build                    # writes dist/PipePlug.fmu and the rest
    python -m pipeplug_fmu build --dest out/X.fmu   # PipePlug.fmu as out/X.fmu, the rest in out/

(``python build_fmu.py`` in the repository does the same.) ``--dest`` names PipePlug.fmu's
file; everything else is written into the same folder:

* ``Hammer.fmu``: the blow train (:mod:`~pipeplug_fmu.blows`, :mod:`~pipeplug_fmu.hammer`);
* ``fmi3/PipePlug.fmu``, ``fmi3/Hammer.fmu``: the same slaves as FMI 3.0 co-simulation FMUs
  (pythonfmu3, :mod:`~pipeplug_fmu.fmi3`), PipePlug with the profile arrays;
* ``PipeRamming.ssp``, ``OspSystemStructure.xml``, ``PipePlug_OspModelDescription.xml`` and
  ``Hammer_OspModelDescription.xml``: Hammer driving PipePlug (:mod:`~pipeplug_fmu.systems`).

Each FMU's resources hold a script ``<prefix>_slave_<tag>.py`` and one package
``<prefix>_fmu_<tag>`` (prefix ``pipeplug`` or ``hammer``): the adapter's run-time modules of
that FMU, for PipePlug with the core beside them as ``pipeplug_fmu_<tag>.pipeplug``. ``<tag>`` is
a digest of the content of everything shipped: pythonfmu runs all FMUs of a process in one
interpreter and imports their modules by name, so Hammer's modules never meet PipePlug's, a
rebuilt FMU with changed code gets names of its own and never runs another build's code, while
two copies of the same build share modules that are identical anyway. An FMU needs nothing from
this repository; its ``documentation/index.html`` is generated from the same tables it
registers its variables from, so the two cannot disagree.

pythonfmu writes each zip with its own binaries; the build then compiles the loader
(:mod:`pipeplug_fmu.native`, with the ``ziglang`` package, once per FMU with its model
identifier and the guid or instantiationToken pythonfmu gave it) and puts it at
``binaries/linux64/<modelIdentifier>.so``, pythonfmu's linux64 binary beside it as
``<modelIdentifier>_pythonfmu.so``; for FMI 3.0 the same with the FMI 3.0 loader in
``binaries/x86_64-linux/`` before pythonfmu3's binary. The win64 binaries are pythonfmu's and
pythonfmu3's, unchanged.
"""
from __future__ import annotations

import argparse
import hashlib
import shutil
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from .native import compile_loader, inner_name, model_token, platform_folder
from .pythonfmu07 import SCRIPT

__all__ = ["build", "build_fmu", "stage", "install_loader", "main", "DEFAULT_DEST", "FMUS",
           "FMUS3", "FMI3_FOLDER"]

DEFAULT_DEST = Path("dist") / "PipePlug.fmu"
_ADAPTER = Path(__file__).resolve().parent
_TAG_LENGTH = 12


@dataclass(frozen=True)
class FmuKind:
    """What one of the project's FMUs is made of."""

    identifier: str            # modelIdentifier, the slave's class name and binaries' names
    prefix: str                # of the shipped script and package names
    module: str                # the adapter module holding the slave class
    runtime: tuple             # the adapter modules shipped
    with_core: bool            # ship the core as <package>.pipeplug
    documentation: str         # the adapter module with documentation_html()
    slave: str = ""            # FMI 3.0: the version-neutral slave class the script extends


#: The FMI base every FMU ships: base (with its call sequence and FMU states), its pythonfmu 0.7
#: workarounds, the interface helpers, and the FMI 2.0 binding.
_BASE = ("base.py", "sequence.py", "fmu_state.py", "pythonfmu07.py", "fmi.py", "fmi2.py")

#: The project's FMUs by modelIdentifier.
FMUS = {
    "PipePlug": FmuKind("PipePlug", "pipeplug", "fmi2_pipeplug",
                        ("__init__.py", "slave.py", "fmi2_pipeplug.py", *_BASE), True,
                        "documentation"),
    "Hammer": FmuKind("Hammer", "hammer", "fmi2_hammer",
                      ("__init__.py", "hammer.py", "fmi2_hammer.py", "blows.py", *_BASE), False,
                      "hammer_documentation"),
}

#: The FMI 3.0 base: the same, with the FMI 3.0 binding instead of FMI 2.0's.
_BASE3 = (*_BASE[:-1], "fmi3.py")

#: The project's FMI 3.0 FMUs by modelIdentifier: the same slaves; the class is defined in the
#: script (pythonfmu3 finds it there by its text).
FMUS3 = {
    "PipePlug": FmuKind("PipePlug", "pipeplug3", "slave", ("__init__.py", "slave.py", *_BASE3),
                        True, "documentation", "PipePlugSlave"),
    "Hammer": FmuKind("Hammer", "hammer3", "hammer", ("__init__.py", "hammer.py", "blows.py",
                                                      *_BASE3), False, "hammer_documentation",
                      "HammerSlave"),
}

#: Where the FMI 3.0 FMUs go, beside the FMI 2.0 ones.
FMI3_FOLDER = "fmi3"

#: The FMI 3.0 slave script (pythonfmu3 imports it once and finds the class by the text of its
#: ``class`` line, which must name Fmi3Slave).
SCRIPT3 = '''"""The {cls} slave of build {tag}, FMI 3.0 (see pipeplug_fmu.build)."""
from pythonfmu3 import Fmi3Slave

from {prefix}_fmu_{tag}.fmi3 import Fmi3Binding
from {prefix}_fmu_{tag}.{module} import {slave}

__all__ = ["{cls}"]


class {cls}({slave}, Fmi3Binding, Fmi3Slave):  # Fmi3Slave: named for pythonfmu3's class search
    pass
'''


def build(dest: Path = DEFAULT_DEST) -> list[Path]:
    """Build PipePlug.fmu at ``dest`` and, in its folder, Hammer.fmu and the system files (the
    rectangular blows' beside the FMUs, the ram's in the subfolder ``ram``).

    Returns every path written, PipePlug.fmu's first.
    """
    from .systems import RAM_FOLDER, ram_system, write_systems

    dest = Path(dest).resolve()
    pipeplug = build_fmu("PipePlug", dest)
    hammer = build_fmu("Hammer", dest.with_name("Hammer.fmu"))
    fmi3 = [build_fmu(name, dest.parent / FMI3_FOLDER / f"{name}.fmu", 3) for name in FMUS3]
    return [pipeplug, hammer, *write_systems(dest.parent, pipeplug, hammer),
            *write_systems(dest.parent / RAM_FOLDER, pipeplug, hammer, ram_system()), *fmi3]


def build_fmu(identifier: str, dest: Path, version: int = 2) -> Path:
    """Build the FMU ``identifier`` (a key of :data:`FMUS`) at ``dest`` for FMI ``version`` (2
    or 3); return its path."""
    import importlib

    if version == 3:
        from pythonfmu3 import FmuBuilder
    else:
        from pythonfmu import FmuBuilder

    kind = (FMUS3 if version == 3 else FMUS)[identifier]
    dest = Path(dest).resolve()
    dest.parent.mkdir(parents=True, exist_ok=True)
    documentation = importlib.import_module(f"{__package__}.{kind.documentation}")
    with tempfile.TemporaryDirectory(prefix=f"{kind.prefix}_build_") as tmp:
        script, package = stage(Path(tmp) / "stage", identifier, version)
        docs = Path(tmp) / "documentation"
        docs.mkdir()
        (docs / "index.html").write_text(documentation.documentation_html(version),
                                         encoding="utf-8")
        if version == 3:
            # pythonfmu3 writes <modelIdentifier>.fmu into a folder
            built = Path(FmuBuilder.build_FMU(
                script, dest=Path(tmp) / "out", project_files=[package],
                documentation_folder=docs, canGetAndSetFMUState=True,
                canSerializeFMUState=True, canHandleVariableCommunicationStepSize=True,
                needsExecutionTool=True))
            fmu = Path(shutil.move(str(built), str(dest)))
            loader = compile_loader(Path(tmp) / f"{identifier}.so", identifier, 3,
                                    model_token(fmu, 3))
            install_loader(fmu, loader, identifier, 3)
            return fmu
        fmu = Path(FmuBuilder.build_FMU(
            script, dest=dest, project_files=[package], documentation_folder=docs,
            canGetAndSetFMUstate=True, canSerializeFMUstate=True,
            canHandleVariableCommunicationStepSize=True, needsExecutionTool=True))
        loader = compile_loader(Path(tmp) / f"{identifier}.so", identifier, 2,
                                model_token(fmu, 2))
        install_loader(fmu, loader, identifier)
        return fmu


def install_loader(fmu: Path, loader: Path, identifier: str = "PipePlug",
                   version: int = 2) -> None:
    """Rewrite the zip ``fmu`` (FMI ``version``): the loader becomes <identifier>.so in its
    linux64 binaries' folder, pythonfmu's binary moves beside it as
    :func:`~pipeplug_fmu.native.inner_name`; all else is copied."""
    folder = platform_folder(version)
    binary = f"{folder}/{identifier}.so"
    inner = f"{folder}/{inner_name(identifier)}"
    rewritten = fmu.with_suffix(".rewriting")
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(rewritten, "w") as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename == binary:
                dst.writestr(_renamed(info, inner), data)
                data = loader.read_bytes()
            dst.writestr(info, data)
    rewritten.replace(fmu)


def _renamed(info: zipfile.ZipInfo, name: str) -> zipfile.ZipInfo:
    """A copy of ``info`` (date, permissions, compression) under another ``name``."""
    copy = zipfile.ZipInfo(name, info.date_time)
    copy.compress_type, copy.external_attr = info.compress_type, info.external_attr
    return copy


def stage(folder: Path, identifier: str = "PipePlug", version: int = 2) -> tuple[Path, Path]:
    """Write the slave script of FMU ``identifier`` (FMI ``version``) and its package into
    ``folder``; return both paths.

    The package is the FMU's adapter modules (plus the core for PipePlug), without compiled
    caches; its name and the script's carry the digest of their content.
    """
    kind = (FMUS3 if version == 3 else FMUS)[identifier]
    files = [(name, _ADAPTER / name) for name in kind.runtime]
    if kind.with_core:
        import pipeplug

        core = Path(pipeplug.__file__).resolve().parent
        files += [(f"pipeplug/{p.relative_to(core).as_posix()}", p)
                  for p in sorted(core.rglob("*.py"))]
    digest = hashlib.sha256()
    for relative, path in files:
        digest.update(relative.encode() + b"\0" + path.read_bytes() + b"\0")
    tag = digest.hexdigest()[:_TAG_LENGTH]
    package = folder / f"{kind.prefix}_fmu_{tag}"
    for relative, path in files:
        target = package / relative
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(path, target)
    script = folder / f"{kind.prefix}_slave_{tag}.py"
    script.write_text((SCRIPT3 if version == 3 else SCRIPT).format(
        tag=tag, prefix=kind.prefix, module=kind.module, cls=identifier, slave=kind.slave),
        encoding="utf-8")
    return script, package


def main(argv: list[str] | None = None) -> int:
    """Command line: ``[build] [--dest PATH]``."""
    parser = argparse.ArgumentParser(
        prog="python -m pipeplug_fmu",
        description="Build dist/PipePlug.fmu, dist/Hammer.fmu and the system files "
                    "PipeRamming.ssp and OspSystemStructure.xml (with the OSP model "
                    "descriptions) beside them.")
    parser.add_argument("command", nargs="?", choices=("build",), default="build",
                        help="what to do (only: build)")
    parser.add_argument("--dest", type=Path, default=DEFAULT_DEST,
                        help=f"where to write PipePlug.fmu (default: {DEFAULT_DEST}); the other "
                             f"files go into the same folder")
    for path in build(parser.parse_args(argv).dest):
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
