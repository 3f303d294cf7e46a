"""Every hard case of the catalogue on every solver it applies to, against its exact reference.

The catalogue (:mod:`pipeplug_harness.stability.cases`) lists the cases and their independent
references: the closed form of model I (pulse by pulse from rest, pulls mirrored), a hand
derivation for one body under a train of blows, d'Alembert for the free elastic pipe, and the
exact solver as the limit of fd and elastic for loads with no closed form. Each row must stay
finite, meet its tolerance, balance its energy and, once the motion has ended, stay at rest
with exactly zero velocity for 10^4 more steps (10^6 in ``test_long_runs.py``).
"""
from __future__ import annotations

import numpy as np
import pytest

from pipeplug_harness.stability.cases import CATALOGUE
from pipeplug_harness.stability.runs import (
    build_for,
    energy_residual,
    errors,
    long_run,
    reference_for,
    run_case,
    tolerance,
)

ROWS = [(case, solver) for case in CATALOGUE for solver in case.solvers]


@pytest.mark.parametrize("case, solver", ROWS, ids=[f"{c.name}-{s}" for c, s in ROWS])
def test_hard_case(case, solver):
    model = build_for(case, solver)
    out = run_case(case, model)
    assert all(np.all(np.isfinite(v)) for v in out.values()), "non-finite output"
    ref = reference_for(case, out["time"])
    if ref is not None:
        err_v, err_u = errors(out, ref, case)
        tol_v, tol_u = tolerance(case, solver)
        assert err_v <= tol_v and err_u <= tol_u, (
            f"{case.name} / {solver}: errors v {err_v:.3e}, u {err_u:.3e} "
            f"> tolerance {tol_v:g}, {tol_u:g} ({case.reference})")
    energy = energy_residual(model, out)
    if solver == "fd":
        assert energy >= -1e-12, energy          # the scheme only dissipates
    else:
        assert abs(energy) <= (1e-12 if solver == "exact" else 1e-6), energy
    late = long_run(case, model, solver, 10_000)
    assert late["finite"]
    if case.stops:
        assert late["drift_v"] == 0.0 and late["drift_u"] == 0.0, (
            f"{case.name} / {solver}: moves after it stopped: speed up to "
            f"{late['drift_v']:.3e} m/s, creep {late['drift_u']:.3e} m")


def test_catalogue_covers_the_issue():
    """Every kind of hard case of the issue is in the catalogue (names are the index)."""
    names = " ".join(c.name for c in CATALOGUE)
    for word in ("boundary I/II", "boundary I/III", "boundary II/IV", "boundary III/IV",
                 "boundary IV/V", "point", "Fig. 4 curve 3", "Fig. 5 curve 5", "tau1 = 0",
                 "tau2 = 0", "tau1 = tau2 = 0", "1000 tau*", "1e-6", "1e3", "pulled back",
                 "train", "no grid", "long communication", "short communication", "grazing",
                 "Courant 1", "Courant 0.1", "soft plug", "short blow"):
        assert word in names, word
