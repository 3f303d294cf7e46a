"""Compile the core's kernels into the on-disk cache: ``python warm_kernels.py PACKAGE [PATH]``.

Runs a few steps of every kind of model of the core ``PACKAGE`` (``pipeplug``, or a copy inside
an unpacked FMU, importable from ``PATH``), so that every kernel is compiled once and cached
(:mod:`pipeplug.jit`) before the tests start: otherwise each process of a test run that needs
a kernel before another has cached it compiles it again (a compile costs seconds to tens of
seconds), both test workers often the same kernels at the same time.
"""
from __future__ import annotations

import importlib
import sys


def run_every_kind(core) -> None:
    """A few steps (and samples) of each model and kernel of ``core``; a blow on the batch."""
    def steps(params, options, strike=None):
        model = core.build_model(params, options)
        if strike:
            model.strike(strike)
        model.sample(2e4, [1e-3, 2e-3])
        model.advance_to(0.0, 3e-3)
        model.outputs()
        model.set_state(model.get_state())  # the rigid solvers' piece start: a kernel of its own

    for growth in (False, True):
        steps({"tau1": 2e4}, {"contact_growth": growth})
        for tau1 in (0.0, 2e4):
            for L2 in (0.0, 1.0):
                steps({"tau1": tau1, "L2": L2, "dx": 0.05},
                      {"elastic": True, "contact_growth": growth})
    steps({"tau1": 2e4, "ram_mass": 50.0}, {}, 3.0)
    steps({"tau1": 2e4, "ram_mass": 50.0, "dx": 0.05}, {"elastic": True}, 3.0)
    # Smith damping's kernel: the damping tests, the fuzz's Dask workers and its FMU cases
    # (seeds 201:0 and 202:125) would each compile it
    steps({"tau1": 2e4, "L2": 1.0, "dx": 0.05, "J_shaft": 0.5}, {"elastic": True})
    steps({"tau1": 2e4, "L2": 0.0, "dx": 0.05, "J_shaft": 0.5},
          {"elastic": True, "plug_growth": True})
    importlib.import_module(core.__name__ + ".batch").blows({"tau1": 2e4})


if __name__ == "__main__":
    sys.path[:0] = sys.argv[2:3]
    run_every_kind(importlib.import_module(sys.argv[1]))
