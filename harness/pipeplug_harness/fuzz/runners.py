"""Running one case: through a core path, the reference, or the FMU.

Every run returns the outputs after each step as rows in the order of
:data:`pipeplug.OUTPUT_NAMES` (13 columns; ``at_rest`` and the modes as numbers).
Models advance with ``advance_to`` to absolute times, as hosts step.
"""
from __future__ import annotations

import atexit
import copy
from pathlib import Path

import numpy as np

from pipeplug import OUTPUT_NAMES

from .cases import Case, loads_on, strikes_on_calls

__all__ = ["run_grid", "run_calls", "run_reference", "fmu_host", "drop_fmu_host", "COLUMN"]

#: output name -> column of a run's rows
COLUMN = {name: i for i, name in enumerate(OUTPUT_NAMES)}


def run_grid(builder, case: Case, grid, probe_rest: bool = False,
             params=None, options=None) -> tuple[np.ndarray, int]:
    """Advance a fresh model through the communication points ``grid`` [s] (``grid[0]`` = 0).

    Parameters
    ----------
    builder : callable
        ``(params, options) -> model`` (a core path).
    case : Case
    grid : sequence of float
        Increasing times [s] from 0.
    probe_rest : bool
        At the first point of each stretch where ``at_rest`` holds, step a copy of the model
        under Q = 0 and count a violation unless its velocities are 0 and its outputs stay
        the same, bit for bit.
    params, options : dict, optional
        Override the case's parameters and options (the fd runs).

    Returns
    -------
    (rows, rest_violations)
        Outputs after each step, shape ``(len(grid) - 1, 13)``, and the violation count.
    """
    grid = np.asarray(grid, dtype=float)
    return _advance(builder, case, grid[:-1], grid[1:], probe_rest, params, options)


def run_calls(builder, case: Case, calls) -> np.ndarray:
    """Replay an FMU host's ``(current time, step size)`` calls on a core path: each step
    ends at ``current time + step size``, as in the FMU."""
    starts = np.array([t for t, _ in calls])
    ends = np.array([t + h for t, h in calls])
    return _advance(builder, case, starts, ends, False, None, None)[0]


def _advance(builder, case, starts, ends, probe_rest, params, options):
    model = builder(params or case.params, options or case.options)
    loads = loads_on(case.segments, starts)
    rows = np.empty((len(ends), len(OUTPUT_NAMES)))
    violations, resting = 0, False
    for i in range(len(ends)):
        model.advance_to(float(loads[i]), float(ends[i]))
        out = model.outputs()
        rows[i] = out
        if probe_rest and out.at_rest and not resting:
            violations += _rest_violated(model, out, float(ends[i]), case.stop)
        resting = out.at_rest
    return rows, violations


def _rest_violated(model, out, t: float, stop: float) -> int:
    """1 if ``at_rest`` is claimed wrongly: velocities not 0, or a step under Q = 0 changes
    an output."""
    probe = copy.deepcopy(model)
    probe.advance_to(0.0, t + max(stop, 1.0))
    after = probe.outputs()
    return int(out.v_pipe != 0.0 or out.v_plug != 0.0 or tuple(after) != tuple(out))


def run_reference(case: Case, times, params=None) -> dict:
    """The independent reference (DOP853, :mod:`pipeplug_references.rigid_ivp`,
    :mod:`pipeplug_references.face_ivp` with end resistance, or
    :mod:`pipeplug_references.damping_ivp` with Smith damping) at ``times``; ``W_face`` and
    ``W_damping`` are 0 where their effect is absent."""
    params = dict(params or case.params)
    if any(params.get(k, 0.0) for k in ("J_shaft", "J_face")):
        from pipeplug_references.damping_ivp import simulate_damped

        return simulate_damped(params, case.segments, times, case.growth)
    for k in ("J_shaft", "J_face"):
        params.pop(k, None)
    faces = {k: params.pop(k, 0.0) for k in ("q_face", "q_plug_face")}
    zeros = np.zeros(len(np.atleast_1d(times)))
    if any(faces.values()):
        from pipeplug_references.face_ivp import simulate_face

        out = simulate_face({**params, **faces}, case.segments, times, case.growth)
        out["W_damping"] = zeros
        return out
    from pipeplug_references.rigid_ivp import simulate

    out = simulate(params, case.segments, times, case.growth)
    out["W_face"], out["W_damping"] = zeros, zeros
    return out


class FmuHost:
    """One FMU instance (:class:`pipeplug_harness.session.FmuSession`), restarted for every case
    of a process."""

    def __init__(self, fmu: str | Path):
        from pipeplug_harness.session import FmuSession
        self.session = FmuSession(fmu, name="fuzz")

    def run(self, case: Case, calls) -> np.ndarray:
        """Reset, set the case's parameters, make the host's calls; the outputs after each."""
        loads = loads_on(case.segments, [t for t, _ in calls])
        return self.run_with(case.params, case.options, loads, calls)

    def run_with(self, params: dict, options: dict, loads, calls, strikes=()) -> np.ndarray:
        """Reset, set ``params`` and ``options`` (by contract name), make the host's ``calls``
        with ``loads[i]`` held over call ``i`` and each strike ``(time [s], velocity [m/s])``
        of ``strikes`` started by the call from its time (:func:`~.cases.strikes_on_calls`);
        the outputs after each."""
        self.session.restart({**params, **options})
        at = strikes_on_calls(calls, strikes)
        rows = np.empty((len(calls), len(OUTPUT_NAMES)))
        for i, (t, h) in enumerate(calls):
            if i in at:
                self.session.strike(at[i])
            rows[i] = self.session.step(t, h, float(loads[i]))
        return rows

    def close(self) -> None:
        self.session.close()


_HOSTS: dict[str, FmuHost] = {}


def fmu_host(fmu: str | Path) -> FmuHost:
    """The process's one instance of the FMU at ``fmu`` (a file or an extracted folder)."""
    key = str(Path(fmu).resolve())
    if key not in _HOSTS:
        if not _HOSTS:
            atexit.register(_close_all)
        _HOSTS[key] = FmuHost(key)
    return _HOSTS[key]


def drop_fmu_host(fmu: str | Path) -> None:
    """Forget the instance after it failed (the next case gets a new one; a failed pythonfmu
    instance is never terminated: that can crash the host)."""
    _HOSTS.pop(str(Path(fmu).resolve()), None)


def _close_all() -> None:
    for host in _HOSTS.values():
        host.close()
    _HOSTS.clear()
