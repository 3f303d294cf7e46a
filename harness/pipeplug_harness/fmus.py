"""Where a command finds the FMUs it needs, from any folder.

``--fmu PATH`` names one. Without it the command takes the FMUs built from the installed code:
``<cache>/fmu/<digest>/PipePlug.fmu`` (with Hammer.fmu and the system files beside it, the FMI
3.0 FMUs in ``fmi3/``, which ``--fmi 3`` chooses), where
``<digest>`` is a digest of the content of everything a build ships (the core, the adapter,
their versions) and ``<cache>`` is ``PIPEPLUG_CACHE_DIR`` or the user's cache folder
(``~/.cache/pipeplug``). When that folder is missing the FMUs are built into it once (about a
minute; ``python -m pipeplug_fmu build`` in a subprocess), into a temporary folder first, which
is renamed into place whole: two commands building at once never see half a build.
"""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path
from xml.etree import ElementTree

from pipeplug_harness.errors import RunFailed, UserError

__all__ = ["cache_root", "build_digest", "cached_build", "find_fmu", "BUILD_FILES",
           "FMI_VERSIONS", "add_fmi_argument"]

#: the files of a build, PipePlug.fmu first
BUILD_FILES = ("PipePlug.fmu", "Hammer.fmu", "PipeRamming.ssp", "OspSystemStructure.xml")
_SHIPPED = (".py", ".c", ".h")
#: The FMI versions of the FMUs a build holds (``--fmi``), and the folder of each.
FMI_VERSIONS = (2, 3)
_FMI_FOLDER = {2: ".", 3: "fmi3"}


def add_fmi_argument(parser) -> None:
    """The ``--fmi`` option of a command that runs PipePlug.fmu."""
    parser.add_argument("--fmi", type=int, default=2, choices=FMI_VERSIONS,
                        help="the FMI version of the FMU to run (%(default)s; 3: the build's "
                             "fmi3/PipePlug.fmu)")


def cache_root() -> Path:
    """``PIPEPLUG_CACHE_DIR``, else the user's cache folder ``.../pipeplug``."""
    root = os.environ.get("PIPEPLUG_CACHE_DIR")
    if root:
        return Path(root)
    if sys.platform.startswith("win"):
        base = os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local"
    elif sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    else:
        base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "pipeplug"


def build_digest() -> str:
    """A digest of the content of everything a build ships: the core's and the adapter's
    sources, and the versions of pythonfmu and Python it is built with."""
    import pipeplug
    import pipeplug_fmu
    h = hashlib.sha256()
    for package in (pipeplug, pipeplug_fmu):
        root = Path(package.__file__).resolve().parent
        for path in sorted(p for p in root.rglob("*") if p.suffix in _SHIPPED
                           and "__pycache__" not in p.parts):
            h.update(str(path.relative_to(root.parent)).encode())
            h.update(path.read_bytes())
    try:
        from importlib.metadata import version
        h.update(version("pythonfmu").encode())
        h.update(version("pythonfmu3").encode())
    except Exception:                          # not installed: the build will say so
        pass
    h.update(f"{sys.version_info[:2]}".encode())
    return h.hexdigest()[:16]


def cached_build(build=None) -> Path:
    """PipePlug.fmu of the installed code in the per-user cache, built there when missing
    (``build(folder)`` writes the build into ``folder``; default: the adapter's build command in
    a subprocess)."""
    folder = cache_root() / "fmu" / build_digest()
    fmu = folder / BUILD_FILES[0]
    try:
        if fmu.is_file():
            return fmu
        folder.parent.mkdir(parents=True, exist_ok=True)
        work = Path(tempfile.mkdtemp(prefix=".building-", dir=folder.parent))
    except OSError as exc:                     # a cache folder of another user, say
        raise UserError(f"the FMU cache cannot be used ({type(exc).__name__}: "
                        f"{exc.strerror or exc}); give --fmu, or set PIPEPLUG_CACHE_DIR to a "
                        f"folder of your own", file=folder.parent) from None
    try:
        print(f"pipeplug: building the FMUs of this installation into {folder} (once)",
              file=sys.stderr, flush=True)
        (build or _build)(work)
        try:
            os.rename(work, folder)
        except OSError:                        # another command finished the same build first
            if not fmu.is_file():
                raise
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return fmu


def _build(folder: Path) -> None:
    proc = subprocess.run([sys.executable, "-m", "pipeplug_fmu", "build", "--dest",
                           str(folder / BUILD_FILES[0])], capture_output=True, text=True,
                          check=False)
    if proc.returncode:
        last = (proc.stderr.strip().splitlines() or ["no message"])[-1]
        raise RunFailed(f"building the FMUs failed (python -m pipeplug_fmu build): {last}")


def find_fmu(given=None, name: str = "PipePlug.fmu", fmi: int = 2) -> Path:
    """The FMU file ``name`` of FMI version ``fmi`` to use: ``given`` (``--fmu``), else the
    cached build's.

    Raises
    ------
    UserError
        When ``given`` does not exist, cannot be read or is not an FMU, or ``fmi`` is not one
        of :data:`FMI_VERSIONS`.
    """
    if fmi not in FMI_VERSIONS:
        raise UserError(key="--fmi", value=fmi, allowed=", ".join(map(str, FMI_VERSIONS)))
    if given is not None:
        return _an_fmu(Path(given), Path(name).stem)
    return (cached_build().parent / _FMI_FOLDER[fmi] / name).resolve()


def _an_fmu(path: Path, model: str) -> Path:
    """``path`` if it is an FMU of ``model`` (a zip, or an unpacked folder, holding
    modelDescription.xml with that modelName), checked before any run: a command given another
    file, or another FMU (Hammer's for PipePlug's), refuses it at once, never counts it as a
    failing case of its run."""
    try:
        if path.is_dir():
            inside = path / "modelDescription.xml"
            description = inside.read_bytes() if inside.is_file() else None
        else:
            with zipfile.ZipFile(path) as archive:
                description = archive.read("modelDescription.xml")
    except FileNotFoundError:
        raise UserError("no such FMU file or folder", file=path) from None
    except OSError as exc:                         # a folder or file the user may not read
        raise UserError(f"cannot be read ({exc.strerror})", file=path) from None
    except (zipfile.BadZipFile, KeyError):
        description = None
    if description is None:
        raise UserError("not an FMU: allowed: an FMU file (a zip holding modelDescription.xml) "
                        "or its unpacked folder", file=path)
    found = _model_name(description)
    if found != model:
        raise UserError(f"is the FMU of modelName = {found!r}; allowed: a {model} FMU",
                        file=path)
    return path


def _model_name(description: bytes) -> str | None:
    """The modelName of a modelDescription.xml's text (None where it has none, or is not XML)."""
    try:
        return ElementTree.fromstring(description).get("modelName")
    except ElementTree.ParseError:
        return None
