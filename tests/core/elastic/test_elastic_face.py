"""End resistance in the elastic model (pipeplug.elastic.face): a rod struck by a step force
whose front end meets the soil's resistance, against d'Alembert; the ledger and W_face.

A rod of impedance Z = S1 sqrt(E1 rho1) under a step Q at x = 0: the front end, free, would
move at 2 Q / Z when the wave reaches it (t = L/c); a resisting end of constant force Qf while
it advances moves at (2 Q - Qf) / Z (the reflected wave carries Q - Qf), and stays at rest,
reflecting as a fixed end, when Qf >= 2 Q. Until the reflection returns to the head (3 L / c)
the front's velocity is that constant. At Courant 1 the scheme transports the waves exactly.
"""
import math

import numpy as np
import pytest

from pipeplug import Params
from pipeplug.elastic.model import ElasticModel
from pipeplug.interface import ledger_residual
from pipeplug.options import Options


def _model(params, growth=False):
    """The plain-Python path (the compiled one gives the same bits; its compilation is the
    elastic fuzz's to pay, not a test's)."""
    p = Params(**params).validate({"elastic"})
    return ElasticModel(p, Options.from_mapping({"elastic": True, "contact_growth": growth}),
                        vectorised=True)


@pytest.mark.parametrize("q_face", [2e6, 20e6])
def test_struck_rod_with_a_resisting_front_end_is_dalembert(q_face):
    params = dict(L1=1.0, dx=0.05, tau2=0.0, q_face=q_face, x_monitor=1.0)
    p = Params(**params)
    q, qf = 5e3, p.F_face
    z, c = p.S1 * math.sqrt(p.E1 * p.rho1), p.c1
    model = _model(params)
    h = model.clock.h
    times = np.arange(1, round(2.9 * p.L1 / c / h)) * h
    out = model.sample(q, times, ["v_pipe", "W_face", "W_input", "E_kinetic", "E_strain"])
    expected = max(2.0 * q - qf, 0.0) / z
    between = (times > p.L1 / c + 2 * h) & (times < 2.9 * p.L1 / c - 2 * h)
    assert out["v_pipe"][between] == pytest.approx(expected, abs=1e-12 * 2 * q / z)
    assert np.all(out["v_pipe"][times < p.L1 / c - 2 * h] == 0.0)
    assert np.all(np.diff(out["W_face"]) >= 0.0)
    assert (out["W_face"][-1] > 0.0) == (qf < 2 * q)
    residual = out["W_input"] - out["E_kinetic"] - out["E_strain"] - out["W_face"]
    assert np.abs(residual).max() <= 1e-12 * out["W_input"].max()


@pytest.mark.parametrize("growth", [False, True])
def test_ledger_closes_with_plug_faces_soil_and_a_ram(growth):
    params = dict(L1=1.0, L2=0.5, dx=0.05, tau1=2e4, tau2=3e4, q_face=3e6, q_plug_face=2e6,
                  ram_mass=20.0, cushion_stiffness=1e7)
    model = _model(params, growth)
    rows = []
    for k, t in enumerate(np.linspace(0.0, 0.03, 61)[1:]):
        if k in (0, 30):
            model.strike(6.0)
        model.advance_to(1e4 if t < 0.01 else -5e3 if t < 0.02 else 0.0, t)
        rows.append(model.outputs())
    w_face = np.array([r.W_face for r in rows])
    assert w_face[-1] > 0.0 and np.all(np.diff(w_face) >= 0.0)
    scale = max(r.W_input + r.W_ram for r in rows)
    assert max(abs(ledger_residual(r)) for r in rows) <= 1e-12 * scale
