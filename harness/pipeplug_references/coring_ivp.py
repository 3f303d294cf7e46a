"""Reference for a plug that grows: rigid pipe and rigid plug taking in soil at rest (scipy).

Independent of the core (never imports it). A frictionless pipe (no soil friction, no end
resistance) of mass M1 cores the soil: its plug, of length L (from L0, possibly 0) and mass
m = rho2 S2 L, slides in it against the friction tau2 P2 L while the pipe is faster; soil at
rest joins the plug at the pipe's front end, so the length grows at the relative velocity and
the plug's momentum changes by the friction alone (the soil that joins brings none)::

    dL/dt  = v1 - v2                  (while v1 > v2)
    dp/dt  = tau2 P2 L (1 + J (v1 - v2))          p = m v2, the plug's momentum
    M1 dv1/dt = Q(t) - tau2 P2 L (1 + J (v1 - v2))

``J`` = ``J_shaft`` [s/m] is Smith's damping of the sliding friction (0 by default): its
damper dissipates ``integral of tau2 P2 L J (v1 - v2)^2 dt``.

When the plug reaches the pipe's velocity the two stick and move on together (no relative
advance: no more soil enters; under Q = 0 at a constant velocity). Momentum is conserved:
``M1 v1 + p = M1 v1(0) + integral of Q``; the energy the soil's uptake dissipates is
``integral of (1/2) rho2 S2 (v1 - v2) v2^2 dt`` (each mass dm taken up at rest costs dm v2^2/2),
and the friction's ``integral of tau2 P2 L (v1 - v2) dt``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["simulate_coring"]


def simulate_coring(p: dict, force: float, duration: float, times) -> dict:
    """The coring pipe under ``force`` [N] for ``duration`` [s] from rest, then free, at
    ``times`` [s].

    Parameters
    ----------
    p : dict
        L1, L2 (the starting length) [m], R1, h1 [m], rho1, rho2 [kg/m3], tau2 [Pa],
        optionally J_shaft [s/m].

    Returns
    -------
    dict of arrays
        ``v_pipe``, ``v_plug`` [m/s], ``u_pipe`` [m], ``L2_now`` [m], ``W_accretion``,
        ``W_friction_inner`` (the Coulomb part), ``W_damping``, ``W_input`` [J].
    """
    S1 = math.pi * ((p["R1"] + p["h1"]) ** 2 - p["R1"] ** 2)
    S2 = math.pi * p["R1"] ** 2
    M1, rho_s = p["rho1"] * S1 * p["L1"], p["rho2"] * S2
    grip = 2.0 * math.pi * p["R1"] * p["tau2"]          # tau2 P2, friction per metre [N/m]
    damping = float(p.get("J_shaft", 0.0))
    times = np.asarray(times, dtype=float)

    def plug_velocity(L, mom):
        return mom / (rho_s * L) if L > 0.0 else 0.0

    def rates(t, y):
        u1, v1, L, mom, w_acc, w_fr, w_in, w_damp = y
        q = force if t < duration else 0.0
        v2 = plug_velocity(L, mom)
        slip = max(v1 - v2, 0.0)
        f = grip * L if v1 > v2 else 0.0
        g = f * damping * slip                          # the damper's force
        return [v1, (q - f - g) / M1, slip, f + g, 0.5 * rho_s * slip * v2 * v2, f * slip,
                q * v1, g * slip]

    def stuck(t, y):
        return y[1] - plug_velocity(y[2], y[3]) if t > 0.0 else 1.0
    stuck.terminal, stuck.direction = True, -1

    y0 = [0.0, 0.0, p["L2"], 0.0, 0.0, 0.0, 0.0, 0.0]
    out = np.empty((8, times.size))
    y = np.array(y0)
    pieces = [(0.0, duration), (duration, float(times[-1]))]
    for start, end in pieces:
        if end <= start:
            continue
        sol = solve_ivp(rates, (start, end), y, method="DOP853", rtol=1e-11, atol=1e-14,
                        dense_output=True, events=stuck if start >= duration else None)
        stop = sol.t[-1]
        inside = (times >= start) & (times <= stop)
        if inside.any():
            out[:, inside] = sol.sol(times[inside])
        y = sol.y[:, -1]
        if stop < end:                                  # stuck: together at one velocity
            after = times > stop
            v = (M1 * y[1] + y[3]) / (M1 + rho_s * y[2])
            out[:, after] = np.array([y[0] + v * (times[after] - stop), v + 0 * times[after],
                                      y[2] + 0 * times[after], rho_s * y[2] * v
                                      + 0 * times[after], *(y[4:, None] + 0 * times[after])])
            break
    u1, v1, L, mom, w_acc, w_fr, w_in, w_damp = out
    v2 = np.where(L > 0.0, mom / (rho_s * np.where(L > 0.0, L, 1.0)), 0.0)
    return {"u_pipe": u1, "v_pipe": v1, "v_plug": v2, "L2_now": L, "W_accretion": w_acc,
            "W_friction_inner": w_fr, "W_input": w_in, "W_damping": w_damp}
