"""Model III with a plug that grows and clean-outs (pipeplug.elastic.growth)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug import build_model
from pipeplug.elastic.growth import CELLS, LENGTH, GrowthModel
from pipeplug.elastic.kernels import KERNELS
from pipeplug.elastic.model import ElasticModel
from pipeplug.interface import ledger_residual
from pipeplug.options import Options
from pipeplug.params import ParameterError, Params
from pipeplug_references.coring_ivp import simulate_coring

GROWTH = {"elastic": True, "plug_growth": True}
PIPE = dict(L1=2.0, R1=0.1, h1=0.01, rho1=7800.0, rho2=1800.0, E1=2e11, E2=6e8, dx=0.125,
            tau1=0.0, tau2=5e3, x_monitor=1.0)


def _model(vectorised=False, options=GROWTH, **changes):
    opts = Options.from_mapping(options)
    params = Params.from_mapping({**PIPE, **changes}).validate(opts.active_groups())
    cls = GrowthModel if opts.plug_growth else ElasticModel
    return cls(params, opts, vectorised=vectorised)


def _blows(model, force, blows=3, on=40, off=200, cleanout_at=()):
    """A train of blows of ``on`` internal steps every ``on + off``; the outputs after every
    step, a clean-out before the blows of ``cleanout_at``."""
    h, rows = model.clock.h, []
    for b in range(blows):
        if b in cleanout_at:
            model.clean_out()
        for k in range(on + off):
            model.advance(force if k < on else 0.0, h)
            rows.append(model.outputs())
    return rows


def _allowance(rows, steps):
    largest = max(max(abs(getattr(o, n)) for n in ("W_input", "W_ram", "W_friction",
                                                     "W_accretion", "W_removed", "W_face",
                                                     "W_damping"))
                  for o in rows)
    return (1e-12 + 2.2e-16 * steps) * largest


def test_the_defaults_build_the_model_of_before():
    model = build_model(PIPE, {"elastic": True})
    assert type(model) is ElasticModel
    assert model.kernel_name in {k.__name__ for k in KERNELS.values()}
    out = model.outputs()
    assert (out.L2_now, out.W_accretion, out.W_removed) == (1.0, 0.0, 0.0)
    with pytest.raises(ParameterError, match="cleanouts"):
        model.clean_out()
    with pytest.raises(ParameterError, match="plug_growth"):       # the fd scheme: none
        build_model(PIPE, {"plug_growth": True, "solver": "fd"})


@pytest.mark.parametrize("changes", [
    dict(L2=0.0),                                              # from an empty pipe
    dict(L2=0.5, tau1=2e4, q_face=2e6, q_plug_face=3e5),       # soil, both faces
    dict(L2=0.25, tau1=1e4, ram_mass=300.0),                   # a ram at the head
    dict(L2=0.0, tau1=1e4, q_face=2e6, q_plug_face=3e5, J_shaft=0.5, J_face=0.3),  # damped
])
def test_ledger_closes_and_the_works_never_decrease(changes):
    model = _model(**changes)
    strike = "ram_mass" in changes
    if strike:
        model.strike(6.0)
    rows = _blows(model, 0.0 if strike else 4e5, cleanout_at=(2,))
    steps = len(rows)
    worst = max(abs(ledger_residual(o)) for o in rows)
    assert worst <= _allowance(rows, steps)
    for name in ("W_accretion", "W_friction", "W_face", "W_damping"):
        values = np.array([getattr(o, name) for o in rows])
        assert np.all(np.diff(values) >= 0.0), name
    assert (rows[-1].W_damping > 0.0) == ("J_shaft" in changes)
    assert all(o.E_kinetic >= 0.0 and o.E_strain >= 0.0 for o in rows)
    lengths = np.array([o.L2_now for o in rows])
    assert lengths.max() > changes["L2"] + 0.02       # it grew by coring
    if not changes.get("q_plug_face"):     # (a face held at rest takes soil in at rest)
        assert rows[-1].W_accretion > 0.0


@pytest.mark.parametrize("damping", [{}, dict(J_shaft=0.5, J_face=0.3, q_face=2e6)])
def test_the_path_without_numba_gives_the_same_bits(damping):
    runs = []
    for vectorised in (False, True):
        model = _model(vectorised, L2=0.0, tau1=1e4, q_plug_face=2e5, **damping)
        runs.append(np.array(_blows(model, 4e5, blows=2, on=20, off=60, cleanout_at=(1,)),
                             dtype=float))
    assert runs[0].tobytes() == runs[1].tobytes()


def test_a_plug_that_fills_the_pipe_takes_in_nothing_and_steps_as_without_growth():
    # L2 = L1: no soil can enter (the pipe is plugged); with end resistance both models run
    # the same projections: the same bits as the elastic model without growth
    changes = dict(L2=2.0, tau1=1e4, q_face=1e6, q_plug_face=2e5)
    grown = _blows(_model(**changes), 5e5, blows=2)
    fixed = _blows(_model(options={"elastic": True}, **changes), 5e5, blows=2)
    assert np.array(grown, dtype=float).tobytes() == np.array(fixed, dtype=float).tobytes()
    assert all(o.L2_now == 2.0 and o.W_accretion == 0.0 for o in grown)


def test_growth_stops_when_the_plug_fills_the_pipe():
    model = _model(L2=1.5, tau2=200.0)
    rows = _blows(model, 6e5, blows=6)
    lengths = np.array([o.L2_now for o in rows])
    assert lengths[-1] == 2.0 and lengths.max() == 2.0         # L1 exactly, never beyond
    full = np.argmax(lengths == 2.0)
    after = np.array([o.W_accretion for o in rows[full:]])
    assert np.all(after == after[0])                           # plugged: nothing joins
    assert int(model.acc[CELLS]) == model.grid.n1


def test_a_pipe_moving_back_relative_to_the_plug_takes_in_nothing():
    # pulled back from rest, the pipe drags the plug back more slowly: the plug moves forward
    # relative to the pipe; nothing enters, nothing leaves, the ledger closes
    model = _model(L2=0.5)
    h, rows = model.clock.h, []
    for _ in range(600):
        model.advance(-4e5, h)
        rows.append(model.outputs())
    assert rows[-1].v_pipe < rows[-1].v_plug < 0.0
    assert all(o.L2_now == 0.5 and o.W_accretion == 0.0 for o in rows)
    assert max(abs(ledger_residual(o)) for o in rows) <= _allowance(rows, 600)


def test_without_plug_friction_the_length_follows_the_front_end():
    # tau2 = 0: the soil that enters is not coupled and stays at rest; a free pipe pushed at
    # Courant 1 never moves its front end back, so L2_now = L2 + the front end's advance
    model = _model(L2=0.25, tau2=0.0, x_monitor=2.0)
    rows = _blows(model, 3e5, blows=2)
    front = np.array([o.u_pipe for o in rows])
    assert np.all(np.diff(front) >= 0.0) and front[-1] > 0.02
    np.testing.assert_allclose([o.L2_now - 0.25 for o in rows], front, rtol=1e-12, atol=0.0)
    assert all(o.W_accretion == 0.0 and o.v_plug == 0.0 for o in rows)


def test_a_cleanout_removes_the_kinetic_energy_of_the_soil_it_takes():
    model = _model(L2=1.0, L2_after_cleanout=0.3)       # 0.3 m: 2 whole cells of 0.125 m
    d, j0 = model._plug()
    speed = 2.5
    model.v1[:] = speed
    model.v2[j0:] = speed                               # a plug moving as one, unstrained
    model._rest = None
    model.acc[LENGTH] = 1.0 + 0.3 * 0.125                   # a fraction of a cell: 1.0375 m
    before = model.outputs()
    model.clean_out()
    after = model.outputs()
    removed = (1.0375 - 0.25) * 1800.0 * math.pi * 0.1 ** 2     # the mass taken out [kg]
    assert after.L2_now == 0.25
    assert after.W_removed == pytest.approx(0.5 * removed * speed ** 2, rel=1e-12)
    assert ledger_residual(after) == pytest.approx(ledger_residual(before), abs=1e-9)
    model.clean_out()                                    # already that short: nothing
    assert model.outputs() == after


def test_cleanouts_refused_without_a_plug_that_grows():
    with pytest.raises(ParameterError, match="cleanouts"):
        _model(options={"elastic": True}, L2=0.5).clean_out()


@pytest.fixture(scope="module", params=[0.0, 0.5], ids=["undamped", "J_shaft=0.5"])
def coring_errors(request):
    """The coring reference (rigid pipe and plug, soil at rest joining; with Smith damping of
    the plug's friction at ``J_shaft``) against model III on 16, 32 and 64 cells, the rods'
    stiffness growing as 1/dx^2 so that their elastic difference to rigid bodies shrinks with
    dx too. Returns the errors and the names compared."""
    base = dict(PIPE, L2=0.5, x_monitor=0.0, J_shaft=request.param)
    names = ("L2_now", "W_accretion", "u_pipe") + (("W_damping",) if request.param else ())
    force, duration, stop = 2e5, 4e-3, 0.012
    times = np.linspace(0.001, stop, 12)
    ref = simulate_coring(base, force, duration, times)
    if request.param:
        assert ref["W_damping"][-1] > 0.05 * ref["W_input"][-1]   # the damper matters
    errors = []
    for n1 in (16, 32, 64):
        E1 = 2e11 * (n1 / 8) ** 2
        model = _model(**dict(base, dx=2.0 / n1, E1=E1, E2=E1 * 1800.0 / 7800.0))
        h = model.clock.h
        end = round(duration / h) * h
        model.advance_to(force, end)
        later = times > end
        out = model.sample(0.0, times[later], names=names)
        errors.append([float(np.max(np.abs(out[k] - ref[k][later])) / np.max(np.abs(ref[k])))
                       for k in names])
    return np.array(errors), names


def test_coring_approaches_the_variable_mass_reference_at_first_order(coring_errors):
    errors, names = coring_errors
    dx = np.array([1.0, 0.5, 0.25])
    for column, name in enumerate(names):
        order = np.polyfit(np.log(dx), np.log(errors[:, column]), 1)[0]
        assert order > 0.8, (name, order, errors[:, column])
    assert errors[-1, 0] < 2e-4 and errors[-1, 1] < 2e-2
