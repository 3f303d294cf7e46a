"""Cases, sample grids, references and error measures of the ``cost`` study.

Every method is run on the same :class:`BenchCase`: a rectangular pulse (Q0 for t < t0, then 0)
from rest, sampled on a uniform grid of ``rate`` samples per second that contains t0; the study's
cases share one grid of :data:`SAMPLES` times (to :data:`T_END`, past every stop). Model I cases
are measured against the closed form (:mod:`pipeplug_references.closed_form`); the model II case
(``contact_growth``) has no closed form and is measured against the core's exact solver.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from pipeplug_harness.paper import RIGID_PARAMETERS, to_symbols
from pipeplug_references.closed_form import Case, figure_cases, solution, stop_times

#: model parameters of the core taken from a closed-form case (the pulse is the driver's)
MODEL_KEYS = RIGID_PARAMETERS
#: samples per second of the common grid; 1/rate = 0.2 ms is the paper's step, t0 = 250 samples
RATE = 5000
#: samples of every case of the study: 2,000 at 0.2 ms, to T_END
SAMPLES = 2000
#: last sample time of the study's cases, s (past the last stop of every case that stops)
T_END = SAMPLES / RATE
#: horizon of a short case whose bodies never stop, s
OPEN_HORIZON = 0.2
#: the study's outputs: pipe and plug velocity (m/s) and displacement (m)
KEYS = ("V1", "V2", "U1", "U2")


@dataclass(frozen=True)
class BenchCase:
    """One case of the study.

    Attributes
    ----------
    name : str
        Short label used in tables (e.g. ``"III"``, ``"II-model2"``).
    case : Case
        Pulse and parameters (SI).
    growth : bool
        True for model II (outer contact over the penetrated length).
    t_end : float
        Last sample time, s (a multiple of 1/`rate`).
    rate : int
        Samples per second.
    """

    name: str
    case: Case
    growth: bool
    t_end: float
    rate: int = RATE

    @cached_property
    def times(self) -> np.ndarray:
        """Sample times k / rate, k = 1 .. rate t_end, s (t0 is one of them)."""
        return np.arange(1, round(self.t_end * self.rate) + 1) / self.rate

    @cached_property
    def loads(self) -> np.ndarray:
        """Struck-end force over the sample interval ending at each sample time, N."""
        return np.where(self.times <= self.case.t0, self.case.Q0, 0.0)

    @property
    def params(self) -> dict:
        """Parameter mapping for :func:`pipeplug.build_model`."""
        return {k: getattr(self.case, k) for k in MODEL_KEYS}

    @property
    def options(self) -> dict:
        """Option mapping of the rigid model (solver added by the caller)."""
        return {"contact_growth": True} if self.growth else {}


def horizon(case: Case, rate: int = RATE, margin: float = 1.25) -> float:
    """Run length, s: `margin` times the last stop time (`OPEN_HORIZON` if a body never stops).

    Rounded up to the sample grid.
    """
    finite = [t for t in stop_times(case) if math.isfinite(t)]
    end = margin * max(finite + [case.t0]) if len(finite) == 2 else OPEN_HORIZON
    return math.ceil(end * rate - 1e-9) / rate


def _pick(fig: str, index: int) -> Case:
    return figure_cases()[fig][index]


def default_cases() -> list[BenchCase]:
    """Model I: one case per moving domain (I-IV) and the frictionless-outer one; one model II case.

    Paper's curves: Fig. 4 curves 2 and 4 (domains I, III), Fig. 6a curves 4 and 6 (II, IV),
    Fig. 5 curve 1 (tau1 = 0, Fig. 7's case); model II: Fig. 6b curve 4. Every case runs on the
    same :data:`SAMPLES` sample times, to :data:`T_END`.
    """
    chosen = [("I", _pick("4", 1)), ("II", _pick("6a", 3)), ("II-tau1=0", _pick("5", 0)),
              ("III", _pick("4", 3)), ("IV", _pick("6a", 5))]
    model2 = _pick("6a", 3)                          # Fig. 6b, curve 4: the same taus as model I
    cases = [BenchCase(n, c, False, T_END) for n, c in chosen]
    cases.append(BenchCase("model-II", model2, True, T_END))
    return cases


def quick_cases() -> list[BenchCase]:
    """Two short model I cases (domains III and IV) for the tests, each to 1.25 times its last
    stop."""
    return [replace(c, t_end=horizon(c.case)) for c in default_cases() if c.name in ("III", "IV")]


def creep_cases(cases: list[BenchCase], after: float = 0.1) -> list[BenchCase]:
    """The model I cases whose pipe stops, run `after` s beyond the plug's stop."""
    out = []
    for c in cases:
        stops = stop_times(c.case)
        if not c.growth and all(map(math.isfinite, stops)) and stops[0] > 0.0:
            out.append(replace(c, t_end=math.ceil((max(stops) + after) * c.rate) / c.rate))
    return out


def closed_form_reference(bench: BenchCase, times: np.ndarray | None = None) -> dict:
    """Closed-form V1, V2, U1, U2 at `times` (default: the sample times), model I only."""
    ref = solution(bench.case, bench.times if times is None else times)
    return {k: ref[k] for k in KEYS}


def from_outputs(columns: dict) -> dict:
    """Core output names (v_pipe, ...) -> the study's keys (V1, ...)."""
    return to_symbols(columns)


def relative_errors(result: dict, ref: dict) -> tuple[float, float]:
    """Maximum velocity and displacement errors of both bodies, relative to the reference's peaks.

    Returns
    -------
    (float, float)
        max |V - V_ref| / max |V1_ref| and max |U - U_ref| / max |U1_ref| over the samples, 1.
    """
    v_scale = float(np.max(np.abs(ref["V1"])))
    u_scale = float(np.max(np.abs(ref["U1"])))
    v_err = max(float(np.max(np.abs(result[k] - ref[k]))) for k in ("V1", "V2"))
    u_err = max(float(np.max(np.abs(result[k] - ref[k]))) for k in ("U1", "U2"))
    return v_err / v_scale, u_err / u_scale
