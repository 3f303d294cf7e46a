"""Single-blow chunks through the core's batch API: one call of :func:`pipeplug.batch.blows`
per chunk instead of one model per case.

For the sweeps of :data:`.runners.BATCH_RULES` (rigid, exact, one blow from rest at t = 0, no
mode sequence) the batch API runs what the per-case path (:mod:`.cases`) runs: the same
functions of the exact solver, through the blow and then under Q = 0 in steps doubling from
the blow's duration, the last cut at ``stop_time``. Its results are the displacements and works
once all is at rest and the end of the last step (``t_end``); the other outputs are what at
rest under no load means: velocities 0, friction forces 0 (both contacts stuck with nothing to
hold), modes (0, 0), ``at_rest`` true, ``W_friction`` the sum of its two parts.

Two things go to the per-case path, so that their rows read exactly as there: the cases not at
rest by ``stop_time`` (e.g. tau1 = 0: nothing stops the pipe; their outputs are taken while
moving), and a chunk the batch API refuses (a value out of range: each case then gets its own
``error``).
"""
from __future__ import annotations

import numpy as np
import pyarrow as pa

from pipeplug.params import PARAMETERS

from .cases import case_rows, schema
from .sample import varied_values

__all__ = ["run_chunk", "AT_REST"]

#: the outputs of a rigid model at rest under Q = 0 (the batch API reports the others): no
#: motion, no energy stored, none dissipated by the exact solution's numerics
AT_REST = {"v_pipe": 0.0, "v_plug": 0.0, "F_outer": 0.0, "F_inner": 0.0, "E_kinetic": 0.0,
           "E_strain": 0.0, "W_numerical": 0.0, "F_head": 0.0, "v_ram": 0.0, "W_ram": 0.0,
           "W_cushion": 0.0, "stress_head": 0.0, "stress_min": 0.0, "stress_max": 0.0,
           "at_rest": True, "pipe_mode": 0, "plug_mode": 0}
#: result columns taken as the batch API gives them
_GIVEN = ("u_pipe", "u_plug", "W_input", "W_friction_outer", "W_friction_inner", "t_end")
_PARAMS = frozenset(p.name for p in PARAMETERS)
_L2_DEFAULT = next(p.default for p in PARAMETERS if p.name == "L2")


def run_chunk(spec, c: int) -> pa.Table:
    """The rows of chunk ``c`` of the sweep ``spec``: the same columns as
    :func:`.cases.run_chunk`, the values to round-off."""
    from pipeplug.batch import blows
    start, stop = spec.chunk_range(c)
    n = stop - start
    varied = varied_values(spec.dims, spec.sampling, spec.seed, start, stop)
    base, given = spec.base, spec.base["blows"]
    params = {k: v for k, v in base.items() if k in _PARAMS and v is not None}
    params.update({k: v for k, v in varied.items() if k in _PARAMS})
    amplitude, duration = (varied.get(k, given[k]) for k in ("amplitude", "duration"))
    stop_time = base["output"]["stop_time"]
    if not np.all(np.asarray(duration) <= stop_time):     # the per-case path words the refusal
        return case_rows(spec, varied, start, range(n))
    try:
        out = blows(params, amplitude, duration, bool(base["contact_growth"]), t_max=stop_time)
    except (ValueError, RuntimeError):    # a refused value (ParameterError), a solver failure
        return case_rows(spec, varied, start, range(n))
    columns = {"case": np.arange(start, stop, dtype=np.int64), **varied,
               **{k: out[k] for k in _GIVEN},
               "W_friction": out["W_friction_outer"] + out["W_friction_inner"],
               "E_transferred": out["W_input"],                # no ram: Q's own work
               "W_face": np.zeros(n),          # sweep files set no end resistance
               # nor a growing plug: the plug keeps its length
               "L2_now": np.broadcast_to(np.asarray(params.get("L2", _L2_DEFAULT), dtype=float),
                                         (n,)).copy(),
               "W_accretion": np.zeros(n), "W_removed": np.zeros(n),
               **{k: np.full(n, v) for k, v in AT_REST.items()},
               "error": pa.repeat("", n)}
    table = pa.table(columns, schema=schema(spec))
    moving = ~np.isfinite(out["t_rest"])
    if not moving.any():
        return table
    rest = case_rows(spec, varied, start, np.flatnonzero(moving).tolist())
    return pa.concat_tables([table.filter(pa.array(~moving)), rest]).sort_by("case")
