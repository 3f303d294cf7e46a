"""Running the cases of a sweep through the core (no FMU), one model per case: one task = one
chunk of cases.

:func:`run_chunk` is what a worker runs (unless the sweep takes the batch API, :mod:`.batch`);
it depends only on the sweep and the chunk's number,
so every worker, in any order and any number of times, gives the same table for it. A case that
fails (a refused parameter, a solver error) gives a row with its ``error`` and empty results;
the other cases go on.

* blow: the model is built from the case's values (:func:`pipeplug.build_model`), takes the
  blows of [blows] (Q held over each, 0 between them), then goes on under Q = 0 in steps
  doubling from the blow's duration until all is at rest or ``stop_time``. Row: the outputs at
  the end, ``t_end`` [s], and, when the sweep wants them (:attr:`~.file.SweepSpec.modes`),
  ``modes``: the contact modes the run went through, e.g. ``"(1,1),(1,-1),(0,-1),(0,0)"``
  (``(pipe_mode, plug_mode)`` as in the outputs).
* drive: the whole drive of :mod:`pipeplug_harness.drive.run` on a core model
  (:class:`~pipeplug_harness.session.CoreSession`). Row: outcome, blows, penetration, ...
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pyarrow as pa

from pipeplug.interface import OUTPUTS
from pipeplug_harness.errors import UserError
from pipeplug_harness.session import split_start_values
from pipeplug_harness.spec import blow_train, elastic_choice

from .sample import varied_values

__all__ = ["run_chunk", "case_rows", "prepare", "schema", "modes_text", "RESULT_COLUMNS",
           "RESULT_UNITS"]

_ARROW = {"Real": pa.float64(), "Integer": pa.int64(), "Boolean": pa.bool_()}

#: kind -> (column, arrow type) of its results, after the case index and the varied names
RESULT_COLUMNS = {
    "blow": [(o.name, _ARROW[o.kind]) for o in OUTPUTS]
            + [("t_end", pa.float64()), ("modes", pa.string())],
    "drive": [("outcome", pa.string()), ("refusal", pa.bool_()), ("blows", pa.int64()),
              ("penetration", pa.float64()), ("last_set", pa.float64()),
              ("drive_time", pa.float64()), ("metres_per_hour", pa.float64()),
              ("steps", pa.int64())],
}

#: kind -> column -> unit of its results (SI; the others have none: counts, flags, modes, text)
RESULT_UNITS = {
    "blow": {**{o.name: o.unit for o in OUTPUTS}, "t_end": "s"},
    "drive": {"penetration": "m", "last_set": "m", "drive_time": "s", "metres_per_hour": "m/h"},
}


@dataclass
class BlowCase:
    """A single-blow case ready to run: the built model and its load."""

    model: object
    pulses: list          #: (start [s], duration [s], amplitude [N]) of each blow
    stop_time: float      #: [s]
    elastic: bool


def schema(spec) -> pa.Schema:
    """The columns of the sweep's output: case, the varied names, the results (``modes`` only
    when the sweep wants them), error."""
    results = [c for c in RESULT_COLUMNS[spec.kind] if c[0] != "modes" or spec.modes]
    return pa.schema([("case", pa.int64())] + [(d.name, pa.float64()) for d in spec.dims]
                     + results + [("error", pa.string())])


def prepare(kind: str, values: dict):
    """Check a case's values with the core and make it ready to run.

    Returns
    -------
    BlowCase or DriveSpec

    Raises
    ------
    UserError or pipeplug.ParameterError
        Naming the offending value and what is allowed.
    """
    if kind == "drive":
        from pipeplug_harness.drive.file import drive_spec
        return drive_spec("case", values)
    return _prepare_blow(values)


def _prepare_blow(values: dict) -> BlowCase:
    from pipeplug import build_model
    blows, output = values.pop("blows"), values.pop("output")
    values.pop("checks", None)
    elastic, _ = elastic_choice(values.pop("elastic"), values, blows["duration"])
    params, options = split_start_values({k: v for k, v in values.items() if v is not None})
    options["elastic"] = elastic
    train = blow_train(blows)
    if train.count < 1:
        raise UserError(f"[blows] count = {train.count}; allowed: >= 1 (a sweep's case ends)")
    pulses = [(train.start + k * train.period, train.duration, train.amplitude)
              for k in range(train.count)]
    end = pulses[-1][0] + pulses[-1][1]
    if not output["stop_time"] >= end:
        raise UserError(f"[output] stop_time = {output['stop_time']!r}; allowed: >= the end "
                         f"of the blows ({end!r} s)")
    return BlowCase(build_model(params, options), pulses, output["stop_time"], elastic)


def modes_text(modes) -> str:
    """``((1, 1), (1, -1))`` as ``"(1,1),(1,-1)"``."""
    return ",".join(f"({a},{b})" for a, b in modes)


def _run_blow(case: BlowCase) -> dict:
    m = case.model
    for t0, duration, amplitude in case.pulses:
        if t0 > m.time:
            m.advance_to(0.0, t0)
        m.advance_to(amplitude, t0 + duration)
    h = case.pulses[0][1]
    while m.time < case.stop_time and not m.at_rest():
        m.advance_to(0.0, min(case.stop_time, m.time + h))
        h *= 2.0
    return {**m.outputs()._asdict(), "t_end": m.time, "modes": modes_text(m.modes())}


def _run_drive(spec) -> dict:
    from pipeplug_harness.drive.run import run_drive_on_core
    result = run_drive_on_core(spec)
    last = result.blows[-1]
    return {"outcome": result.outcome, "refusal": result.outcome in ("static", "set"),
            "blows": len(result.blows), "penetration": result.penetration,
            "last_set": last.set, "drive_time": result.drive_time,
            "metres_per_hour": result.metres_per_hour, "steps": result.steps}


_RUN = {"blow": _run_blow, "drive": _run_drive}


def run_chunk(spec, c: int) -> pa.Table:
    """The rows of chunk ``c`` of the sweep ``spec`` (:class:`~.file.SweepSpec`), one model per
    case."""
    start, stop = spec.chunk_range(c)
    varied = varied_values(spec.dims, spec.sampling, spec.seed, start, stop)
    return case_rows(spec, varied, start, range(stop - start))


def case_rows(spec, varied: dict, start: int, indices) -> pa.Table:
    """The rows of the cases ``start + j`` for ``j`` in ``indices``, one model per case
    (``varied``: name -> the values of the cases from ``start`` on)."""
    rows = []
    for j in indices:
        row = {"case": start + j, **{name: float(v[j]) for name, v in varied.items()}}
        try:
            row.update(_RUN[spec.kind](prepare(spec.kind, spec.case_values(varied, j))))
            row["error"] = ""
        except Exception as exc:             # one bad case must not stop a campaign
            row["error"] = f"{type(exc).__name__}: {exc}"
        rows.append(row)
    return pa.Table.from_pylist(rows, schema=schema(spec))


def chunk_values(spec, c: int) -> dict:
    """name -> the varied values of chunk ``c`` (as :func:`run_chunk` draws them)."""
    start, stop = spec.chunk_range(c)
    return varied_values(spec.dims, spec.sampling, spec.seed, start, stop)


def value_bounds(spec) -> dict:
    """name -> (smallest, largest) of the varied values over all cases."""
    if spec.sampling == "grid":
        return {d.name: (float(np.min(d.values)), float(np.max(d.values))) for d in spec.dims}
    lo = {d.name: np.inf for d in spec.dims}
    hi = {d.name: -np.inf for d in spec.dims}
    step = 1 << 18
    for a in range(0, spec.n_cases, step):
        v = varied_values(spec.dims, spec.sampling, spec.seed, a, min(spec.n_cases, a + step))
        for name, x in v.items():
            lo[name], hi[name] = min(lo[name], float(x.min())), max(hi[name], float(x.max()))
    return {name: (lo[name], hi[name]) for name in lo}
