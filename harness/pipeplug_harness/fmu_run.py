"""Drive dist/PipePlug.fmu with fmpy, as users do: rectangular pulses on communication points.

Every communication step is passed explicitly (fmpy's defaults coarsen quietly), every pulse
edge is a communication point (a duplicated time stamp in the input signal: the step that
starts at an edge sees the new value), and every run must reach its stop time (a refused
``doStep`` is silent in ``simulate_fmu``: the result just ends early).
"""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pipeplug import OUTPUT_NAMES

__all__ = ["Pulse", "Run", "RunIncomplete", "load_signal", "run_fmu", "extracted", "OUTPUTS",
           "DEFAULT_FMU"]

OUTPUTS = OUTPUT_NAMES           # the core's one table of outputs
DEFAULT_FMU = Path("dist") / "PipePlug.fmu"
_EXTRACTED: dict[tuple[str, float], str] = {}


class RunIncomplete(RuntimeError):
    """The FMU refused a step: the run stopped before its stop time."""


@dataclass(frozen=True)
class Pulse:
    """A rectangular blow: ``amplitude`` [N] from ``start`` [s] for ``duration`` [s]."""

    start: float
    duration: float
    amplitude: float

    @property
    def end(self) -> float:
        return self.start + self.duration


@dataclass
class Run:
    """One FMU run: parameters (FMU start values), pulses, communication step, stop time."""

    params: dict = field(default_factory=dict)
    pulses: list = field(default_factory=list)
    step: float = 1e-3
    stop_time: float = 0.2

    def force_at(self, t: np.ndarray) -> np.ndarray:
        """Struck-end force [N] at times ``t`` [s] (right-continuous)."""
        t = np.asarray(t, dtype=float)
        return sum((p.amplitude * ((t >= p.start) & (t < p.end)) for p in self.pulses),
                   np.zeros_like(t))


def load_signal(run: Run) -> np.ndarray:
    """The input signal for fmpy: piecewise-constant Q with each edge on a duplicated stamp."""
    edges = sorted({0.0, run.stop_time} | {e for p in run.pulses for e in (p.start, p.end)
                                           if 0.0 < e < run.stop_time})
    rows = []
    for a, b in zip(edges[:-1], edges[1:]):
        q = float(run.force_at(np.array([0.5 * (a + b)]))[0])
        rows += [(a, q), (b, q)]
    return np.array(rows, dtype=[("time", np.float64), ("Q", np.float64)])


def extracted(fmu: str | os.PathLike) -> str:
    """Extract the FMU once per process into a fixed folder (so JIT caches can hit)."""
    path = Path(fmu).resolve()
    key = (str(path), path.stat().st_mtime)
    if key not in _EXTRACTED:
        from fmpy import extract
        target = Path(tempfile.gettempdir()) / f"pipeplug-fmu-{abs(hash(key)):x}"
        _EXTRACTED[key] = extract(str(path), unzipdir=str(target))
    return _EXTRACTED[key]


def run_fmu(run: Run, fmu: str | os.PathLike = DEFAULT_FMU, outputs=OUTPUTS) -> np.ndarray:
    """Simulate the FMU with fmpy and check the run reached its stop time.

    Parameters
    ----------
    run : Run
        Start values (contract names, SI), pulses, communication step [s], stop time [s].
    fmu : path
        The FMU file.
    outputs : sequence of str
        Output variables to record.

    Returns
    -------
    numpy structured array
        Fields ``time`` and the requested outputs, one row per communication point.

    Raises
    ------
    RunIncomplete
        If the result ends before ``run.stop_time``.
    """
    from fmpy import simulate_fmu
    result = simulate_fmu(
        extracted(fmu), fmi_type="CoSimulation", start_time=0.0, stop_time=run.stop_time,
        output_interval=run.step, start_values=dict(run.params), input=load_signal(run),
        output=list(outputs), validate=False)
    last = float(result["time"][-1])
    if abs(last - run.stop_time) > 1e-9 * max(1.0, run.stop_time):
        raise RunIncomplete(f"run stopped at t = {last:.9g} s before its stop time "
                            f"{run.stop_time:.9g} s (params {run.params})")
    return result
