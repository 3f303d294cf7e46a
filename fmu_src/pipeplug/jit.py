"""Optional compilation of the numeric kernels: numba when it imports, plain Python otherwise.

Kernels and their helpers are written once, as plain Python over floats and arrays. Helpers are
marked with :func:`jitable`; a kernel is compiled by :func:`compiled` when a model first asks
for it. Only then is numba imported (so a model on the plain path, or a host without numba,
never imports it), the marked helpers are registered with numba (they stay plain functions for
Python callers), and the kernel is compiled in ``nopython`` mode with IEEE arithmetic (no
fast-math: the compiled and the Python path give the same numbers). Without numba, or with the
environment variable ``PIPEPLUG_NO_JIT=1``, :func:`compiled` returns the plain function; the
elastic model then does not loop in Python but steps with whole-array numpy operations
(:mod:`pipeplug.elastic.vectorised`, chosen when :func:`enabled` is False). A helper that
Python runs best with array operations and compiled code best as a loop is marked with
:func:`compiled_form`, naming its loop form (both compute the same values with the same
helpers).

Compiled code is cached on disk so that a new process (for example each run of the FMU, whose
files an importer unpacks into a fresh temporary folder and may delete afterwards) reuses it.
numba's own cache is keyed by the source file's folder and needs the file to exist; the
locator below keys it by the content of the package's sources, read when this module is
imported, under ``PIPEPLUG_CACHE_DIR`` or the user's cache folder (``~/.cache/pipeplug``,
``%LOCALAPPDATA%\\pipeplug``). If that folder cannot be written, numba's default locations are
used.
"""
from __future__ import annotations

import hashlib
import os
import sys
from pathlib import Path

__all__ = ["jitable", "compiled_form", "compiled", "specialised", "enabled", "NO_JIT_ENV",
           "CACHE_DIR_ENV", "cache_folder"]

NO_JIT_ENV = "PIPEPLUG_NO_JIT"
CACHE_DIR_ENV = "PIPEPLUG_CACHE_DIR"
_PACKAGE = __name__.rpartition(".")[0] or "pipeplug"
_HELPERS: list = []                 # (function, inline) marked jitable, registered at first compile
_FORMS: list = []                   # (function, its compiled form), registered likewise
_COMPILED: dict = {}                # plain kernel -> its compiled dispatcher
_numba = None                       # the numba module once imported; False when unavailable


def _digest_sources() -> str:
    """A digest of every source of the package (kernels call helpers from other modules; numba
    would not notice a change there). Cached code refers to modules by name: the package's
    import name is part of the key."""
    digest = hashlib.sha256(_PACKAGE.encode())
    root = Path(__file__).resolve().parent
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:20]


_SOURCES_KEY = _digest_sources()    # now, while the files are surely there


def jitable(func=None, *, inline: bool = False):
    """Mark ``func`` as callable from compiled kernels; it is returned unchanged.

    ``inline=True`` (as ``@jitable(inline=True)``): compiled callers get the function's body
    in place of a call, for small functions in hot loops (the compiler does not always inline
    them itself).
    """
    if func is None:
        return lambda f: jitable(f, inline=inline)
    if any(f is func for f, _ in _HELPERS):
        return func
    _HELPERS.append((func, inline))
    if _numba:                      # numba already set up: register now
        _register(func, inline)
    return func


def _register(func, inline: bool) -> None:
    from numba.extending import register_jitable
    register_jitable(inline="always" if inline else "never")(func)


def compiled_form(form):
    """Decorator: compiled kernels that call the decorated function run ``form`` instead.

    ``form`` takes the same arguments and gives the same results, computed in a way that suits
    compiled code (a loop where Python uses array operations); it is marked :func:`jitable`.
    Python callers get the decorated function unchanged.
    """
    def mark(func):
        jitable(form)
        _FORMS.append((func, form))
        if _numba:
            _register_form(func, form)
        return func
    return mark


def _register_form(func, form) -> None:
    """Make compiled calls of ``func`` run ``form`` (a numba overload with its signature)."""
    import inspect

    from numba.extending import overload

    def typer(*args):
        return form
    typer.__signature__ = inspect.signature(form)
    overload(func)(typer)


def enabled() -> bool:
    """True when kernels are compiled (numba importable and not switched off); imports numba."""
    return _load_numba() is not None


def compiled(kernel):
    """The compiled form of ``kernel`` (cached on disk) when numba is enabled, else ``kernel``.

    ``error_model="numpy"`` drops the zero-division checks (the kernels never divide by
    zero); no fast-math, so results equal those of the Python path.
    """
    numba = _load_numba()
    if numba is None:
        return kernel
    if kernel not in _COMPILED:
        _COMPILED[kernel] = numba.njit(cache=True, nogil=True, error_model="numpy")(kernel)
    return _COMPILED[kernel]


def specialised(kernel, *examples):
    """The compiled ``kernel`` for the argument types of ``examples`` alone (cached on disk like
    :func:`compiled`), called without numba's dispatch: typing each argument and choosing a
    compiled version takes about 0.3 µs per call of seven arguments, a share of a small
    model's build and dense output; ``kernel`` itself when numba is not enabled.

    The caller passes exactly those types (arrays of the same dtype, dimensions, layout and
    flags): nothing checks them, and an array of other dimensions would be read out of bounds.
    """
    numba = _load_numba()
    if numba is None:
        return kernel
    return compiled(kernel).compile(tuple(numba.typeof(x) for x in examples))


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
    return Path(root) / "numba" / _SOURCES_KEY


def _load_numba():
    """numba, set up for this package, or None when absent, broken or switched off."""
    global _numba
    if _numba is None:
        _numba = False
        if os.environ.get(NO_JIT_ENV, "").strip() in ("", "0"):
            try:
                import numba
                import numba.extending
            except Exception:  # an absent or broken numba must never stop the pure path
                return None
            _install_cache_locator()
            for helper, inline in _HELPERS:
                _register(helper, inline)
            for func, form in _FORMS:
                _register_form(func, form)
            _numba = numba
    return _numba or None


def _install_cache_locator() -> None:
    """Put compiled kernels of this package in :func:`cache_folder` (best effort)."""
    try:
        from numba.core import caching
    except Exception:
        return
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
    if impl is None or not hasattr(caching, "_CacheLocator"):
        return

    class PipeplugCacheLocator(caching._CacheLocator):
        """numba cache locator keyed by source content; the source file need not exist."""

        package = _PACKAGE        # each copy of the core (FMU builds, FMI versions) has its own

        def __init__(self, py_func, py_file):
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(cache_folder())

        def get_cache_path(self):
            return self._cache_path

        def get_source_stamp(self):
            return _SOURCES_KEY

        def get_disambiguator(self):
            return str(self._lineno)

        @classmethod
        def from_function(cls, py_func, py_file):
            module = getattr(py_func, "__module__", "") or ""
            if not module.startswith(_PACKAGE + "."):
                return None
            self = cls(py_func, py_file)
            try:
                self.ensure_cache_path()
            except OSError:
                return None
            return self

    locators = impl._locator_classes
    if not any(getattr(c, "package", None) == _PACKAGE for c in locators):
        locators.insert(0, PipeplugCacheLocator)
