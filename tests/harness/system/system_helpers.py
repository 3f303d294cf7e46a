"""Helpers of the system tests: the cases, their exact solutions, and the comparison.

Expected values come from the independent references, never from the code under test: the
closed form of model I for one rectangular blow (``pipeplug_references.closed_form``), and the
ODE reference of models I and II under piecewise-constant loads
(``pipeplug_references.rigid_ivp``) for trains. The blow train itself is written here from the
contract (blow k on [start + k period, start + k period + duration), k < count).
"""
from __future__ import annotations

import numpy as np

#: Real outputs of PipePlug compared (the closed form has no split of the friction work).
REAL_OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug", "F_outer", "F_inner", "W_input",
                "W_friction", "W_friction_outer", "W_friction_inner")
CLOSED_FORM_NAMES = {"v_pipe": "V1", "v_plug": "V2", "u_pipe": "U1", "u_plug": "U2",
                     "F_outer": "F_outer", "F_inner": "F_inner", "W_input": "W_input",
                     "W_friction": "W_friction"}
RTOL = 1e-9          # of each quantity's peak over the run

#: name -> (PipePlug values, Hammer values, step [s], stop [s], reference)
CASES = {
    # one blow, model I, domain I: the closed form
    "one blow, model I": ({"tau1": 2e4, "tau2": 1e4}, {"count": 1}, 5e-3, 0.3, "closed form"),
    # three blows that pile up (each arrives while pipe and plug still slide), starting late
    "train, model I": ({"tau1": 2e4, "tau2": 1e4},
                       {"count": 3, "start": 0.01, "amplitude": 23e3, "duration": 0.05,
                        "period": 0.2}, 1e-2, 0.7, "ode"),
    # model II from the soil face: the contact grows blow after blow
    "train, model II": ({"tau1": 5e4, "tau2": 2e4, "contact_growth": True},
                        {"count": 3, "amplitude": 23e3, "duration": 0.04, "period": 0.1},
                        5e-3, 0.35, "ode"),
}


def train_segments(hammer: dict) -> list:
    """The blow train as (duration [s], Q [N]) segments from t = 0 (the ODE reference's load)."""
    amplitude, duration = hammer.get("amplitude", 23e3), hammer.get("duration", 0.05)
    period, count, start = hammer.get("period", 0.2), hammer["count"], hammer.get("start", 0.0)
    segments = [(start, 0.0)] if start > 0 else []
    for _ in range(count):
        segments += [(duration, amplitude), (period - duration, 0.0)]
    return segments


def train_edges(hammer: dict) -> np.ndarray:
    """Every switch time of the train [s]."""
    edges, t = [], 0.0
    for duration, _ in train_segments(hammer):
        t += duration
        edges.append(t)
    return np.array([0.0, hammer.get("start", 0.0), *edges])


def train_force(hammer: dict, t: float) -> float:
    """The train at ``t`` (right-continuous), times compared within 1e-12 s."""
    t_on = 0.0
    for duration, q in train_segments(hammer):
        if t_on - 1e-12 <= t < t_on + duration - 1e-12:
            return q
        t_on += duration
    return 0.0


def reference(pipeplug: dict, hammer: dict, times, kind: str) -> dict:
    """PipePlug's exact outputs at ``times`` under Hammer's train."""
    times = np.asarray(times, dtype=float)
    if kind == "closed form":
        from pipeplug_references.closed_form import Case, solution

        assert hammer["count"] == 1 and hammer.get("start", 0.0) == 0.0
        case = Case(tau1=pipeplug["tau1"], tau2=pipeplug["tau2"],
                    Q0=hammer.get("amplitude", 23e3), t0=hammer.get("duration", 0.05))
        sol = solution(case, times)
        return {name: sol[key] for name, key in CLOSED_FORM_NAMES.items()}
    from pipeplug_references.rigid_ivp import simulate

    params = {k: v for k, v in pipeplug.items() if k in ("tau1", "tau2")}
    sol = simulate(params, train_segments(hammer), times,
                   bool(pipeplug.get("contact_growth", False)))
    return {name: sol[name] for name in REAL_OUTPUTS}


def worst_errors(got: dict, want: dict, times, hammer: dict) -> dict:
    """name -> max |got - want| / peak |want|. Forces are not compared at the train's edges:
    PipePlug reports the force under the step that ends there, the references the one after."""
    times = np.asarray(times, dtype=float)
    at_edge = np.min(np.abs(times[:, None] - train_edges(hammer)[None, :]), axis=1) <= 1e-12
    errors = {}
    for name, expected in want.items():
        keep = ~at_edge if name.startswith("F_") else np.ones(times.size, bool)
        peak = max(float(np.max(np.abs(expected))), 1e-300)
        errors[name] = float(np.max(np.abs(np.asarray(got[name])[keep] - expected[keep]))) / peak
    return errors


def assert_exact(got: dict, pipeplug: dict, hammer: dict, times, kind: str) -> dict:
    """Every compared output within RTOL of its peak; returns the errors (for the report)."""
    errors = worst_errors(got, reference(pipeplug, hammer, times, kind), times, hammer)
    bad = {name: err for name, err in errors.items() if not err <= RTOL}
    assert not bad, f"errors above {RTOL:g} of scale: {bad}"
    return errors
