"""The catalogue of hard cases for dry-friction integrators, each with its exact reference.

A hard case is a load history (rectangular pulses, held constant between communication points)
on a parameter set chosen to sit where dry-friction integrators break: exactly on a domain
boundary of model I, at the points where domains meet, near a boundary (the paper's Fig. 4
curve 3 and Fig. 5 curve 5, docs/corrections.md C1/C2), with a friction limit switched off or far above
the load, with extreme plug masses, with the pipe pulled back, with blows that arrive while
the pipe moves, with load edges on no grid, with communication steps much longer or much
shorter than the spacing of events and the internal step, with simultaneous events (corrections
A7: t3 = t4 = t5 on the I/II boundary), with grazing (velocity and acceleration reach zero
together), and for the elastic model at Courant 1 and below, with a soft plug and a blow much
shorter than the wave round trip.

References (all independent of the solvers, see :mod:`pipeplug_harness.stability.refs`):
``"closed form"`` (model I, pulse by pulse from rest, pulls mirrored), ``"hand"`` (one body
under blows that arrive while it moves), ``"d'Alembert"`` (free elastic pipe), and, for loads
with no closed form, ``"exact solver"``: the exact event-driven solver as the reference of the
fd and elastic solvers (their convergence).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from pipeplug_harness.load import Load
from pipeplug_harness.paper import Q0, RIGID_PARAMETERS, T0
from pipeplug_references import closed_form as cf

__all__ = ["HardCase", "CATALOGUE", "QUICK", "Q0", "T0"]

BASE = cf.Case()                         # the paper's parameters (tau1 = 0, tau2 = 0.01 MPa)
TAU_STAR, GAMMA = BASE.tau_star, BASE.gamma
RHO2_EQUAL_MASS = BASE.rho2 * BASE.M1 / BASE.M2   # plug density giving M2 = M1 [kg/m3]
C2_PAPER = math.sqrt(6.0e8 / 1800.0)              # the paper's plug wave speed [m/s]
F1_20K = BASE.P1 * BASE.L1 * 2.0e4                # outer friction limit at tau1 = 0.02 MPa [N]



@dataclass(frozen=True)
class HardCase:
    """One hard case: parameters, load, sampling, reference and the solvers it applies to.

    ``pulses`` are ``(start [s], duration [s], amplitude [N])``; the load is their sum.
    Outputs are compared at every communication point (multiples of ``step`` and every pulse
    edge). After ``t_end`` the long run holds ``Q = hold`` [N]; ``stops`` says the motion has
    ended by ``t_end``, so nothing may move in the long run. ``elastic`` holds the elastic
    model's extra parameters and ``fd_dt`` the fd solver's largest step [s]; ``tolerance``
    (velocities, displacements) overrides the default tolerance of the reference.
    """

    name: str
    note: str
    params: dict
    pulses: tuple = ((0.0, T0, Q0),)
    t_end: float = 0.3
    step: float = 1e-3
    reference: str = "closed form"
    solvers: tuple = ("exact", "fd", "elastic")
    growth: bool = False
    elastic: dict = field(default_factory=lambda: {"dx": 0.05})
    stops: bool = True
    hold: float = 0.0
    fd_dt: float = 2e-4
    tolerance: tuple | None = None

    def comm_points(self) -> np.ndarray:
        """Communication points after 0 [s]: the step grid, every pulse edge, and ``t_end``."""
        n = int(self.t_end / self.step + 1e-9)
        grid = {round(k * self.step, 12) for k in range(1, n + 1)} | {self.t_end}
        edges = {e for s, d, _ in self.pulses for e in (s, s + d) if 0.0 < e < self.t_end}
        return np.array(sorted(grid | edges))

    @property
    def load_history(self) -> Load:
        """The load of the pulses."""
        return Load.from_pulses(self.pulses)

    def load(self, t: float) -> float:
        """Struck-end force [N] at time ``t`` [s] (right-continuous)."""
        return self.load_history.at(float(t))

    def rigid_case(self, amplitude: float = Q0, duration: float = T0) -> cf.Case:
        """The closed-form case of one pulse on these parameters."""
        values = {k: self.params[k] for k in RIGID_PARAMETERS if k in self.params}
        return replace(BASE, **values, Q0=abs(amplitude), t0=duration)


def _taus(tau1: float, tau2: float, **more) -> dict:
    return {"tau1": float(tau1), "tau2": float(tau2), **more}


_G, _TS = GAMMA, TAU_STAR
_TA = 0.01                          # grazing: blow length [s] ...
_TB = Q0 * _TA / F1_20K             # ... and the exact stop of the pipe alone (hand: Q0 ta/F1)
_RIGID_ONLY = ("exact", "fd")

CATALOGUE: tuple[HardCase, ...] = (
    # Domain boundaries of model I (docs/corrections.md A7) and the points where domains meet.
    HardCase("boundary I/II", "tau1 = gamma tau2: t3 = t4 = t5, pipe stops as the plug sticks",
             _taus(_G * 1e4, 1e4)),
    HardCase("boundary I/III", "tau1 + gamma tau2 = tau*, tau1 = 2 tau2: t1 = t0",
             _taus(2 * _TS / (2 + _G), _TS / (2 + _G))),
    HardCase("boundary II/IV", "tau1 + gamma tau2 = tau*, tau2 = 2 tau1: t1 = t0",
             _taus(0.5 * _TS / (_G + 0.5), _TS / (_G + 0.5))),
    HardCase("boundary III/IV", "tau1 = gamma tau2 >= tau* - gamma tau2: t6 = t7 = t5",
             _taus(_G * 0.4 * _TS, 0.4 * _TS)),
    HardCase("boundary IV/V", "tau1 = tau*: the blow is exactly at the friction limit",
             _taus(_TS, 1e4)),
    HardCase("point I/II/III/IV", "tau1 = gamma tau2 = tau*/2: four domains meet",
             _taus(0.5 * _TS, 0.5 * _TS / _G)),
    HardCase("point I/III/V", "tau1 = tau*, tau2 = 0", _taus(_TS, 0.0)),
    HardCase("point III/IV/V", "tau1 = tau* = gamma tau2", _taus(_TS, _TS / _G)),
    # The paper's near-boundary curves.
    HardCase("Fig. 4 curve 3", "docs/corrections.md C1: domain I, t1 - t0 = 7.3 us", _taus(0.053e6, 0.0265e6)),
    HardCase("Fig. 5 curve 5", "docs/corrections.md C2: domain II, t1 - t0 = 27.8 us", _taus(0.0, 0.0589e6),
             stops=False),
    # Limits switched off or far above the load; extreme plug masses.
    HardCase("tau1 = 0", "no soil friction: the pair never stops", _taus(0.0, 1e4), stops=False),
    HardCase("tau2 = 0", "no plug coupling: the plug is not simulated", _taus(2e4, 0.0)),
    HardCase("tau1 = tau2 = 0", "free flight", _taus(0.0, 0.0), stops=False),
    HardCase("tau1 = 1000 tau*", "nothing moves; the soil holds the whole blow",
             _taus(1e3 * _TS, 1e4)),
    HardCase("plug 1e-6 pipe mass", "M2 = 1e-6 M1 (rho2), plug wave speed kept",
             _taus(2e4, 1e4, rho2=1e-6 * RHO2_EQUAL_MASS),
             elastic={"dx": 0.05, "E2": 1e-6 * RHO2_EQUAL_MASS * C2_PAPER ** 2}),
    HardCase("plug 1e3 pipe mass", "M2 = 1e3 M1 (rho2), plug wave speed kept",
             _taus(2e4, 1e4, rho2=1e3 * RHO2_EQUAL_MASS), t_end=0.4,
             elastic={"dx": 0.05, "E2": 1e3 * RHO2_EQUAL_MASS * C2_PAPER ** 2}),
    # Load histories.
    HardCase("pulled back", "push, rest, pull: the pipe slides back and sticks again",
             _taus(2e4, 1e4), pulses=((0.0, T0, Q0), (0.3, 0.02, -Q0)), t_end=0.45),
    HardCase("model II pulled out", "contact growth, pulled from rest: no soil contact, coasts",
             _taus(2e4, 1e4), pulses=((0.0, T0, -Q0),), growth=True, stops=False,
             reference="closed form, tau1 = 0"),
    HardCase("train while moving", "five blows, each arriving while pipe and plug move",
             _taus(2e4, 1e4), pulses=tuple((0.02 * k, 0.01, Q0) for k in range(5)),
             t_end=0.6, reference="exact solver", solvers=("fd", "elastic")),
    HardCase("train, one body", "three blows on the pipe alone, each arriving while it moves",
             _taus(4e4, 0.0), pulses=((0.0, 0.01, Q0), (0.015, 0.01, Q0), (0.03, 0.005, Q0)),
             t_end=0.1, reference="hand"),
    HardCase("edges on no grid", "blow of 12.3456789 ms: on no step grid", _taus(2e4, 1e4),
             pulses=((0.0, 0.0123456789, Q0),), t_end=0.1),
    HardCase("long communication step", "one step of 0.25 s holds t1, t3 and t4",
             _taus(2e4, 1e4), step=0.3),
    HardCase("short communication step", "steps of 1 us < fd dt and < elastic step",
             _taus(7e4, 3.5e4), t_end=0.08, step=1e-6),
    HardCase("grazing", "stops exactly as Q rises to F1: v = 0 and a = 0 together",
             _taus(2e4, 0.0), pulses=((0.0, _TA, Q0), (_TB, 0.1 - _TB, F1_20K)), t_end=0.1,
             hold=F1_20K, solvers=_RIGID_ONLY),
    HardCase("short blow", "10 us blow, 1/40 of the pipe's wave round trip",
             _taus(2e4, 1e4), pulses=((0.0, 1e-5, 2.3e6),), t_end=0.1, solvers=_RIGID_ONLY,
             fd_dt=2e-5),
    # The elastic model.
    HardCase("elastic Courant 1", "free pipe, 10 us blow (5 steps): exact transport; "
             "displacement lags by dt/2 per front", _taus(0.0, 0.0), pulses=((0.0, 1e-5, Q0),),
             t_end=1e-3, step=2e-6, reference="d'Alembert", solvers=("elastic",),
             elastic={"dx": 0.01}, stops=False, tolerance=(1e-12, 0.05)),
    HardCase("elastic Courant 0.2", "free pipe, 0.1 ms blow at Courant 0.2: fronts smeared",
             _taus(0.0, 0.0), pulses=((0.0, 1e-4, Q0),), t_end=1e-3, step=2e-6,
             reference="d'Alembert", solvers=("elastic",),
             elastic={"dx": 0.01, "courant": 0.2}, stops=False, tolerance=(1.0, 1e-2)),
    HardCase("elastic Courant 0.1, friction", "domain I at Courant 0.1 vs the rigid model",
             _taus(2e4, 1e4), solvers=("elastic",), elastic={"dx": 0.05, "courant": 0.1}),
    HardCase("elastic short blow", "10 us blow with soil and plug friction: no reference",
             _taus(2e4, 1e4), pulses=((0.0, 1e-5, 2.3e6),), t_end=0.1, reference="none",
             solvers=("elastic",)),
    HardCase("soft plug", "E2 = 1e-6 of the paper's: plug wave speed 0.58 m/s",
             _taus(2e4, 1e4), solvers=("elastic",), elastic={"dx": 0.05, "E2": 600.0}),
)

#: The cases of ``pipeplug stability --quick``.
QUICK = ("boundary I/II", "pulled back", "grazing", "elastic Courant 1")
