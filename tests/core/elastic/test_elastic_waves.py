"""Wave transport of the elastic scheme at Courant 1 against d'Alembert's solution."""
from __future__ import annotations

import numpy as np
import pytest
from elastic_helpers import Q0, elastic, impedance


def dalembert_cells(loads, n_cells, impedance_value):
    """Exact cell averages of the velocity of a free-free rod loaded at x = 0.

    With Q piecewise constant on steps of length dx/c (``loads[i]`` on step i), the velocity
    v(x, t) = (1/Z) sum_k [Q(t - (2kL + x)/c) + Q(t - (2(k+1)L - x)/c)] (waves reflected with
    the same sign at the free end and at the force-loaded end) averaged over cell j at
    t = n dx/c is (1/Z) sum_k [Q_(n - 2k n_cells - j - 1) + Q_(n - 2(k+1) n_cells + j)].
    Returns an array (steps, cells).
    """
    loads = np.asarray(loads, float)
    steps = len(loads)
    out = np.zeros((steps, n_cells))
    j = np.arange(n_cells)
    for n in range(1, steps + 1):
        for k in range(steps // (2 * n_cells) + 1):
            for index in (n - 2 * k * n_cells - j - 1, n - 2 * (k + 1) * n_cells + j):
                ok = index >= 0
                out[n - 1, ok] += loads[index[ok]]
    return out / impedance_value


FREE_ROD = dict(tau1=0.0, tau2=0.0, dx=0.05)  # 20 cells, no friction


@pytest.mark.parametrize("substeps", [1, 3])
def test_rectangular_pulses_travel_exactly(substeps):
    """Cell velocities equal the exact cell averages to round-off, over three round trips."""
    model = elastic(FREE_ROD)
    blocks = np.zeros(40)  # loads held over 3 internal steps each: 120 steps of a 20-cell rod
    blocks[:2], blocks[2:4], blocks[10] = 1000.0, -300.0, 500.0
    loads = np.repeat(blocks, 3)
    exact = dalembert_cells(loads, model.grid.n1, impedance(model.params))
    got = []
    for q in loads[::substeps]:
        model.advance(float(q), substeps * model.grid.h_max)
        got.append(model.v1.copy())
    scale = 1000.0 / impedance(model.params)
    assert np.abs(np.array(got) - exact[substeps - 1::substeps]).max() <= 1e-12 * scale


def test_incident_wave_and_free_end_doubling_at_sections():
    model = elastic(FREE_ROD, x_monitor=0.975)  # centre of the last cell
    mid = elastic(FREE_ROD, x_monitor=0.5)      # face between cells 9 and 10
    v_wave = Q0 / impedance(model.params)
    seen_last, seen_mid = [], []
    for _ in range(30):
        for m in (model, mid):
            m.advance(Q0, m.grid.h_max)
        seen_last.append(model.outputs().v_pipe)
        seen_mid.append(mid.outputs().v_pipe)
    # cells 18 and 19 (the last) filled by the incident wave at steps 19 and 20, doubled by its
    # reflection from steps 22 and 21; the centre of the last cell is the mean of its two
    # nodes, the face 18|19 (the mean of the two cells) and the free end (cell 19):
    # 0.25 v18 + 0.75 v19
    np.testing.assert_allclose(seen_last[:18], 0.0, atol=1e-12 * v_wave)
    np.testing.assert_allclose(seen_last[18], 0.25 * v_wave, rtol=1e-12)
    np.testing.assert_allclose(seen_last[19], v_wave, rtol=1e-12)
    np.testing.assert_allclose(seen_last[20], 1.75 * v_wave, rtol=1e-12)
    np.testing.assert_allclose(seen_last[21:], 2.0 * v_wave, rtol=1e-12)
    # midpoint (a face): half the jump as the front crosses it, v_wave behind it
    np.testing.assert_allclose(seen_mid[:9], 0.0, atol=1e-12 * v_wave)
    np.testing.assert_allclose(seen_mid[9], 0.5 * v_wave, rtol=1e-12)
    np.testing.assert_allclose(seen_mid[10:29], v_wave, rtol=1e-12)  # reflection returns at 30
    np.testing.assert_allclose(seen_mid[29], 1.5 * v_wave, rtol=1e-12)


def test_no_odd_even_decoupling_under_a_step_load():
    """docs/corrections.md D6: the cross scheme at Courant 1 alternates 72.1, 5.5, 72.1 m/s at t = 10 ms.

    Here consecutive steps stay within one wave jump Q0/Z of the rigid velocity
    (Q0 - F2) t / M1 (the elastic velocity oscillates around it by at most half a jump, plus
    the friction's waves).
    """
    model = elastic(dx=0.01)
    p = model.params
    for _ in range(5000 // 100):
        model.advance(Q0, 100 * model.grid.h_max)  # to t = 10 ms
    values, times = [], []
    for _ in range(10):
        model.advance(Q0, model.grid.h_max)
        values.append(model.outputs().v_pipe)
        times.append(model.time)
    rigid = (Q0 - p.F2) * np.array(times) / p.M1
    jump = Q0 / impedance(p)
    assert np.abs(np.array(values) - rigid).max() <= jump
    assert np.abs(np.diff(values)).max() <= jump
    behind = model.v1[: model.grid.n1 // 2]
    assert np.ptp(behind) <= 2.0 * jump  # neighbouring cells do not alternate either
