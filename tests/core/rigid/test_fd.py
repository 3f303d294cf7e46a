"""The paper's explicit scheme converges to the exact solver (models I and II)."""
import numpy as np
import pytest
from rigid_helpers import drive

from pipeplug import build_model

Q0, T0 = 23000.0, 0.05
TIMES = np.round(np.arange(1, 201) * 1e-3, 12)       # 1 ms marks to 0.2 s
CASES = [({"tau1": 2e4, "tau2": 1e4}, False),        # domain I
         ({"tau1": 2e4, "tau2": 2e4}, False),        # domain II
         ({"tau1": 7e4, "tau2": 3.5e4}, False),      # domain III
         ({"tau1": 6.5e4, "tau2": 6.5e4}, False),    # domain IV
         ({"tau1": 1.4e4, "tau2": 1.4e4}, True),     # model II
         ({"tau1": 2.8e4, "tau2": 2.8e4}, True)]     # model II


def _errors(params, growth, dts, pulses=((0.0, T0, Q0),)):
    exact = drive(build_model(params, {"contact_growth": growth}), list(pulses), TIMES)
    v_peak = np.abs(exact["v_pipe"]).max()
    u_peak = np.abs(exact["u_pipe"]).max()
    errs = []
    for dt in dts:
        fd = drive(build_model(dict(params, dt=dt), {"solver": "fd", "contact_growth": growth}),
                   list(pulses), TIMES)
        dv = max(np.abs(fd[k] - exact[k]).max() for k in ("v_pipe", "v_plug"))
        du = max(np.abs(fd[k] - exact[k]).max() for k in ("u_pipe", "u_plug"))
        errs.append(max(dv / v_peak, du / u_peak))
    return np.array(errs)


@pytest.mark.parametrize("params, growth", CASES)
def test_fd_converges_with_order_at_least_0_9(params, growth):
    dts = 1e-3 / np.array([2, 5, 10, 20, 40])      # divide the 1 ms communication step
    errs = _errors(params, growth, dts)
    order = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert order >= 0.9, (order, errs)


@pytest.mark.parametrize("params, growth", CASES)
def test_fd_error_at_the_papers_step_is_below_one_percent_of_peak(params, growth):
    assert _errors(params, growth, [2e-4])[0] < 0.01


def test_fd_energy_defect_is_positive_and_first_order():
    # W_input - W_friction - KE = sum M dv^2/2 >= 0 for the scheme, shrinking like dt.
    defects = []
    for dt in (2e-4, 1e-4, 5e-5):
        m = build_model({"tau1": 2e4, "tau2": 1e4, "dt": dt}, {"solver": "fd"})
        m.advance(Q0, T0)
        m.advance(0.0, 0.15)
        o = m.outputs()
        p = m.M1, m.M2
        defects.append(o.W_input - o.W_friction - 0.5 * (p[0] * o.v_pipe ** 2 + p[1] * o.v_plug ** 2))
    assert all(d >= 0 for d in defects)
    assert defects[0] / defects[2] == pytest.approx(4.0, rel=0.2)


def test_fd_negative_q_and_pulse_train_converge():
    pulses = [(0.0, 0.02, Q0), (0.03, 0.0101, -0.8 * Q0), (0.05, 0.0203, Q0)]
    errs = _errors({"tau1": 3e4, "tau2": 1e4}, False, [2e-4, 5e-5, 1.25e-5], pulses)
    assert errs[-1] < errs[0] / 8 and errs[0] < 0.02
