"""Clean-outs of a model III plug (pipeplug.elastic.cleanout, GrowthModel.clean_out)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from pipeplug.elastic.growth import CELLS, LENGTH, GrowthModel
from pipeplug.interface import ledger_residual
from pipeplug.options import Options
from pipeplug.params import Params

GROWTH = Options.from_mapping({"elastic": True, "plug_growth": True})
# the plug's waves are the fastest (c2 = 516 m/s, c1 = 200 m/s): it steps at Courant 1
PLUG = dict(L1=2.0, L2=2.0, R1=0.1, h1=0.01, rho1=7500.0, rho2=1500.0, E1=3e8, E2=4e8,
            dx=0.25, tau1=0.0, tau2=5e3, x_monitor=1.0)


def _model(params, options=GROWTH):
    return GrowthModel(Params.from_mapping(params).validate(options.active_groups()), options)


def _plug_energy(model):
    """The plug's part of the scheme's energy [J] (the pipe's is the rest)."""
    return sum(model._plug_energies())


def test_a_compressed_plug_at_rest_gives_up_the_strain_energy_of_the_soil_taken_out():
    force = 3e5                                      # [N] compression along the whole plug
    model = _model(dict(PLUG, L2_after_cleanout=0.75))
    model.N2[1:-1] = -force                          # every inner face; the ends are free
    model._rest = None
    before = model.outputs()
    model.clean_out()
    after = model.outputs()
    # a bar of length L under the force F holds F^2 L / (2 E S): the 1.25 m taken out held it
    area = math.pi * PLUG["R1"] ** 2
    assert after.W_removed == pytest.approx(force ** 2 * 1.25 / (2.0 * PLUG["E2"] * area),
                                            rel=1e-12)
    assert after.L2_now == 0.75 and model.acc[CELLS] == 3
    assert not model.v2.any()                        # nothing moved: no velocity jump to cut
    assert ledger_residual(after) == pytest.approx(ledger_residual(before), abs=1e-12)


def test_a_plug_oscillating_cell_to_cell_gives_no_energy_to_the_plug_a_cleanout_keeps():
    # Found by the fuzz (seed 2031, case 148): a plug at Courant 1 ringing cell to cell after
    # one blow; velocities held through the cut gave the kept plug 0.0124 J more than the
    # whole plug had, booked as W_removed = -0.0124 J.
    params = dict(L1=7.400705167727246, L2=7.400705167727246, R1=0.3300007621175596,
                  h1=0.0031801000833389654, rho1=7364.173111708957, rho2=1371.3302314843834,
                  E1=310746385.4276309, E2=304305284.65089786, tau1=1690.815332406584,
                  tau2=153.16892360954762, dx=0.9250881459659057, x_monitor=4.474784323097138,
                  L2_after_cleanout=5.550528875795434, q_face=122599.89632042011,
                  q_plug_face=13628.106384775876)
    options = Options.from_mapping({"elastic": True, "plug_growth": True,
                                    "contact_growth": True})
    model = _model(params, options)
    h = model.clock.h
    for k in range(round(0.5557581361663878 / h)):
        model.advance(158564.96268723498 if k * h < 0.011782858010594793 else 0.0, h)
    before = model.outputs()
    model.clean_out()
    after = model.outputs()
    assert after.W_removed > 0.0
    scale = before.W_input
    assert abs(ledger_residual(before)) <= 1e-12 * scale
    assert abs(ledger_residual(after)) <= 1e-12 * scale


@pytest.mark.parametrize("courant", [1.0, 0.6])
def test_a_cleanout_never_gives_energy_to_the_plug_it_keeps(courant):
    # Random plugs (velocities with a cell-to-cell pattern, forces of either sign, a front
    # fraction) cut to 1, 3 and 6 of their 8 cells. The kept plug's momentum changes by
    # -k h^2 (v_c - v_c-1) / 4, a quarter of the change of the cut face's impulse over a step
    # (the scheme's momentum M v summed over the kept cells telescopes to it).
    rng = np.random.default_rng(27)
    for cells in (1, 3, 6):
        model = _model(dict(PLUG, courant=courant, L2_after_cleanout=cells * PLUG["dx"]))
        n, h = model.grid.n1, model.clock.h
        mass = PLUG["rho2"] * math.pi * PLUG["R1"] ** 2 * PLUG["dx"]
        k = PLUG["E2"] * math.pi * PLUG["R1"] ** 2 / PLUG["dx"]
        for _ in range(40):
            model.v2[:] = rng.normal(size=n) + 3.0 * rng.normal() * (-1.0) ** np.arange(n)
            model.N2[1:-1] = k * h * rng.normal(size=n - 1)
            model.acc[LENGTH] = (n + rng.uniform(0.0, 0.99)) * PLUG["dx"]
            model.acc[CELLS] = n
            c = n - cells
            jump = model.v2[c] - model.v2[c - 1]
            momentum = mass * model.v2[c:].sum()
            before, removed = _plug_energy(model), model.outputs().W_removed
            model.clean_out()
            taken = model.outputs().W_removed - removed
            assert taken >= 0.0
            assert taken == pytest.approx(before - _plug_energy(model), abs=1e-12 * before)
            assert mass * model.v2[c:].sum() - momentum == pytest.approx(
                -0.25 * k * h * h * jump, abs=1e-12 * mass * np.abs(model.v2).max())
            assert not model.v2[:c].any() and not model.N2[:c + 1].any()


@pytest.mark.parametrize("length", [5e-35, 0.3 * PLUG["dx"]])
def test_a_first_cell_still_filling_leaves_with_its_kinetic_energy(length):
    # Found by the fuzz (seed 2041, case 125): a plug 5e-35 m long taken out; its energy,
    # a full cell's less (1 - share) of it, came out -5.7e-42 J and was booked as W_removed.
    full_cell = PLUG["rho2"] * math.pi * PLUG["R1"] ** 2 * PLUG["dx"]
    for speed in np.linspace(-3.0, 3.0, 25):
        model = _model(dict(PLUG, L2=0.0, L2_after_cleanout=0.0))
        model.v2[-1] = speed
        model.acc[LENGTH], model.acc[CELLS] = length, 1
        model._rest = None
        model.clean_out()
        after = model.outputs()
        kinetic = 0.5 * full_cell * speed ** 2
        assert after.W_removed >= 0.0 and after.L2_now == 0.0 and not model.v2.any()
        assert after.W_removed == pytest.approx(kinetic * length / PLUG["dx"], rel=1e-12,
                                                abs=1e-15 * kinetic)
