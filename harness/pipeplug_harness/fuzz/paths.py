"""The paths through the core that the fuzz runs every case on.

A path is a builder ``(params, options) -> model`` with the signature of
:func:`pipeplug.build_model`. Every case runs on every path of :data:`CORE_PATHS` (the exact
solver: its plain Python and its compiled form, which without numba is plain Python too) and
is checked on each separately; adding a path is one line in that table. :data:`FD_PATHS` are
the builders of the fd check (options carry ``solver = "fd"`` and parameters the step ``dt``).
Tests register planted defects here under names of their own.
"""
from __future__ import annotations

from functools import partial

from pipeplug import build_model

__all__ = ["CORE_PATHS", "FD_PATHS"]

#: name -> builder of the exact solver on that path
CORE_PATHS = {
    "python": partial(build_model, compiled=False),
    "compiled": partial(build_model, compiled=True),
}
#: name -> builder of the fd scheme
FD_PATHS = {
    "fd": build_model,
}
