"""Optional compilation of the numeric kernels: numba when it imports, plain Python otherwise.

Kernels are written once, as plain loops over float arrays, and decorated with :func:`jit`.
With numba installed they are compiled on first use (``nopython`` mode, IEEE arithmetic: no
fast-math, so the compiled and the Python path give the same numbers); without it, or with the
environment variable ``PIPEPLUG_NO_JIT=1``, they run as ordinary Python.

Compiled code is cached on disk so that a new process (for example each run of the FMU, whose
files an importer unpacks into a fresh temporary folder) reuses it. numba's own cache is keyed
by the source file's folder, which changes with every unpacking; the locator below keys it by
the content of the compiled sources instead, under ``PIPEPLUG_CACHE_DIR`` or the user's cache
folder (``~/.cache/pipeplug``, ``%LOCALAPPDATA%\\pipeplug``). If that folder cannot be written,
numba's default locations are used.
"""
from __future__ import annotations

import functools
import hashlib
import os
import sys
from pathlib import Path

__all__ = ["jit", "ENABLED", "NO_JIT_ENV", "CACHE_DIR_ENV", "cache_folder"]

NO_JIT_ENV = "PIPEPLUG_NO_JIT"
CACHE_DIR_ENV = "PIPEPLUG_CACHE_DIR"
_PACKAGE = __name__.rpartition(".")[0] or "pipeplug"


def _import_numba():
    """The numba module, or None when it is absent, broken or switched off."""
    if os.environ.get(NO_JIT_ENV, "").strip() not in ("", "0"):
        return None
    try:
        import numba
    except Exception:  # an absent or broken numba must never stop the pure path
        return None
    return numba


@functools.lru_cache(maxsize=None)
def _sources_key() -> str:
    """A digest of the package's compiled sources: this module and every module using ``@jit``.

    Kernels call helpers from other modules; numba would not notice a change there, so all of
    them are part of the key (an edit gives a fresh cache folder).
    """
    digest = hashlib.sha256(_PACKAGE.encode())   # cached code refers to modules by name
    for path in sorted(Path(__file__).parent.glob("*.py")):
        content = path.read_bytes()
        if path.name == Path(__file__).name or b"@jit" in content:
            digest.update(path.name.encode())
            digest.update(content)
    return digest.hexdigest()[:20]


def cache_folder() -> Path:
    """The folder holding the compiled kernels of this version of the sources."""
    root = os.environ.get(CACHE_DIR_ENV)
    if not root:
        if sys.platform.startswith("win"):
            base = os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local"
        elif sys.platform == "darwin":
            base = Path.home() / "Library" / "Caches"
        else:
            base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
        root = Path(base) / "pipeplug"
    return Path(root) / "numba" / _sources_key()


def _install_cache_locator(numba) -> None:
    """Put compiled kernels of this package in :func:`cache_folder` (best effort)."""
    try:
        from numba.core import caching
    except Exception:
        return
    base = getattr(caching, "_SourceFileBackedLocatorMixin", None)
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    if base is None or impl is None:
        return

    class PipeplugCacheLocator(base, caching._CacheLocator):
        """numba cache locator keyed by source content, not by the source's folder."""

        def __init__(self, py_func, py_file):
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(cache_folder())

        def get_cache_path(self):
            return self._cache_path

        def get_source_stamp(self):
            # Unpacking an FMU gives its files new modification times; the content decides.
            return _sources_key()

        @classmethod
        def from_function(cls, py_func, py_file):
            if getattr(py_func, "__module__", "").partition(".")[0] != _PACKAGE:
                return None
            return super().from_function(py_func, py_file)

    locators = impl._locator_classes
    if not any(c.__name__ == PipeplugCacheLocator.__name__ for c in locators):
        locators.insert(0, PipeplugCacheLocator)


_numba = _import_numba()
ENABLED: bool = _numba is not None  #: True when kernels are compiled
if ENABLED:
    _install_cache_locator(_numba)


def jit(func):
    """Compile ``func`` with ``numba.njit`` (cached) when numba is enabled, else return it.

    ``error_model="numpy"`` drops the zero-division checks (the kernels never divide by
    zero); no fast-math, so results equal those of the Python path.
    """
    if _numba is None:
        return func
    return _numba.njit(cache=True, nogil=True, error_model="numpy")(func)
