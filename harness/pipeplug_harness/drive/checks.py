"""What every blow of a drive must satisfy, or the drive stops: a result that breaks physics is
never reported.

After each blow (its whole window, to the next blow's start):

* the energy ledger closes: ``|W_input - E_kinetic - E_strain - W_friction - W_numerical|`` at
  most ``(1e-12 + 2.2e-16 n)`` times the largest of those terms, ``n`` the internal steps so far
  (the round-off of the fields grows by about one unit of the last place per step; the works are
  compensated sums); ``E_kinetic`` and ``E_strain`` are >= 0, so friction work never exceeds the
  input work;
* the pipe's velocity stays within what the blows can give it: the rigid pipe's velocity under
  their impulse so far, plus, in the elastic model, a wave of ``2 Q / Z1`` per blow so far (a
  blow's wave doubles at a free end; a train in step with the round trip piles them up) and the
  waves of both frictions ``2 (F1 + F2) / Z1``, all 1.3 times for the elastic scheme's
  overshoot of a front below Courant 1; a hammer's strike at v adds ``2 m v / M1`` and, in the
  elastic model, ``4 v``;
* the front end has not gone back past the start by more than the pipe's elastic shortening
  under the blow, ``Q L1 / (E1 S1)`` (0 in the rigid models): blows push.
* the pipe has not run in beyond its length: the blow has not pushed the front end past
  ``L1`` by more than the pipe's elastic shortening under it (the head would be below the soil
  face while the hammer still drives it: the hammer cannot follow it into the ground), and a
  front end past ``L1`` has come to rest by the next blow's start (else the soil does not hold
  it and the model cannot give where it ends). A pipe that coasts past ``L1`` after its blow
  and is stopped by the soil is a result: the blow that reaches a target of ``L1`` may end past
  it (the summary says by how much).

A violation raises :class:`DriveInvalid` with one line naming the blow and the numbers.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from pipeplug.interface import LEDGER_SOURCES, LEDGER_TERMS, ledger_residual

__all__ = ["DriveInvalid", "Limits", "check_blow", "LEDGER_BASE", "LEDGER_PER_STEP"]

LEDGER_BASE, LEDGER_PER_STEP = 1e-12, 2.2e-16
_SLACK = 1e-9                    # round-off allowance of the bounds (relative)
#: Below Courant 1 the elastic scheme is dispersive: a sharp front overshoots by up to 27 %.
DISPERSION = 1.3


class DriveInvalid(RuntimeError):
    """A blow broke a physical bound or the energy ledger: the run is not a result."""


@dataclass(frozen=True)
class Limits:
    """A drive's constants for the checks (SI), from the contract's formulas."""

    M1: float              #: pipe mass [kg]
    Z1: float              #: pipe impedance [N s/m] (inf: rigid)
    F1: float              #: soil friction limit over the whole pipe [N]
    F2: float              #: plug friction limit (0 without a plug) [N]
    amplitude: float       #: [N]
    duration: float        #: [s]
    rebound: float         #: the largest elastic shortening of the pipe under a blow [m]
    h: float               #: the model's internal step [s] (0: none, the exact solver)

    strike: float = 0.0    #: the ram's velocity at a strike [m/s] (0: no hammer)
    ram_mass: float = 0.0  #: [kg]
    L1: float = math.inf   #: the pipe's length [m]
    holding: float = 0.0   #: what the soil holds the pipe (and the plug in it) back with at
                           #: full length: friction over L1 and the end resistances [N] (the
                           #: plug's friction acts between pipe and plug, and holds neither)

    @classmethod
    def of(cls, spec) -> Limits:
        p = spec.params()
        plug = p.tau2 > 0.0 and p.L2 > 0.0
        v = spec.hammer.v_strike if spec.hammer is not None else 0.0
        if spec.elastic:
            from pipeplug.elastic.grid import build_grid
            Z1, h = p.S1 * math.sqrt(p.E1 * p.rho1), build_grid(p).h_max
            # the head's largest force: the blow's, or twice the ram's Z1 v (the head never
            # outruns the ram, and its wave doubles at the far end)
            rebound = max(spec.amplitude, 2.0 * Z1 * v) * p.L1 / (p.E1 * p.S1)
        else:
            h = p.dt if spec.start_values.get("solver") == "fd" else 0.0
            Z1, rebound = math.inf, 0.0
        F1, F2 = p.P1 * p.L1 * p.tau1, p.F2 if plug else 0.0
        # the plug's face (of a plug that may grow from empty too) pushes the soil ahead
        grows = spec.start_values.get("plug_growth", False)
        face = p.q_face * p.S1 + (p.q_plug_face * p.S2 if p.tau2 > 0.0 and (p.L2 > 0.0 or grows)
                                  else 0.0)
        return cls(p.M1, Z1, F1, F2, spec.amplitude, spec.duration, rebound, h, v, p.ram_mass,
                   p.L1, F1 + face)

    def velocity_bound(self, blows: int) -> float:
        """The largest pipe velocity [m/s] ``blows`` blows can give (module docstring), with
        the overshoot of the elastic scheme's dispersion below Courant 1 (:data:`DISPERSION`).
        A strike at v gives at most the impulse 2 m v (the ram cannot leave faster than it
        came) and, in the elastic model, waves of 4 v (the head never outruns the ram: a wave
        of v at most, doubled at an end and again by the ram's return)."""
        elastic = math.isfinite(self.Z1)
        waves = 2.0 * (blows * self.amplitude + self.F1 + self.F2) / self.Z1
        struck = blows * self.strike * (2.0 * self.ram_mass / self.M1 + (4.0 if elastic
                                                                          else 0.0))
        spread = DISPERSION if elastic else 1.0
        return ((blows * self.amplitude * self.duration / self.M1 + waves) * spread
                + struck) * (1.0 + _SLACK)


def check_blow(limits: Limits, blow, out, t: float, steps: int,
               pushed: float = -math.inf) -> None:
    """Check blow ``blow`` (its record) and the outputs ``out`` at its window's end ``t`` [s]
    (``steps`` communication steps so far: the exact solver's count of pieces at least;
    ``pushed`` the penetration [m] when the blow stopped acting).

    Raises
    ------
    DriveInvalid
        With one line naming the blow and the numbers.
    """
    n = blow.blow
    # W_friction from its two parts, so that a part that is wrong shows in the ledger too
    values = {**out._asdict(), "W_friction": out.W_friction_outer + out.W_friction_inner}
    terms = [values[name] for name in LEDGER_SOURCES + LEDGER_TERMS]
    residual = ledger_residual(values)
    internal = t / limits.h if limits.h else steps
    allowance = (LEDGER_BASE + LEDGER_PER_STEP * internal) * max(map(abs, terms))
    if not abs(residual) <= allowance:
        raise DriveInvalid(
            f"blow {n}: the energy ledger does not close: W_input = {out.W_input:.6g} J, "
            f"E_kinetic = {out.E_kinetic:.6g} J, E_strain = {out.E_strain:.6g} J, W_friction = "
            f"{values['W_friction']:.6g} J, W_numerical = {out.W_numerical:.6g} J leave "
            f"{residual:.3g} J (allowed {allowance:.2g} J)")
    if not (out.E_kinetic >= 0.0 and out.E_strain >= 0.0):
        raise DriveInvalid(f"blow {n}: negative energy: E_kinetic = {out.E_kinetic:.6g} J, "
                           f"E_strain = {out.E_strain:.6g} J")
    bound = limits.velocity_bound(n)
    if not max(abs(blow.v_pipe_peak), abs(blow.v_pipe_end)) <= bound:
        raise DriveInvalid(f"blow {n}: pipe velocity {blow.v_pipe_peak:.6g} m/s exceeds what "
                           f"{n} blows can give it, {bound:.6g} m/s")
    if pushed > limits.L1 + limits.rebound * (1.0 + _SLACK):
        raise DriveInvalid(f"blow {n}: the pipe ran in beyond its length while the blow drove "
                           f"it: penetration {pushed:.6g} m when the blow stopped acting, past "
                           f"L1 = {limits.L1:.6g} m by more than the pipe's elastic shortening "
                           f"({limits.rebound:.3g} m): its head was below the soil face, where "
                           f"the hammer cannot follow; a target short of L1 ends the drive "
                           f"before")
    if blow.penetration > limits.L1 and blow.settled == "moving":
        why = ("nothing in the soil holds it: no shaft friction and no end resistance (tau1 "
               "= q_face = q_plug_face = 0)" if limits.holding == 0.0 else
               f"the soil's hold on the whole pipe, {limits.holding:.4g} N, did not stop it "
               f"before the next blow")
        raise DriveInvalid(f"blow {n}: the pipe ran in beyond its length: penetration "
                           f"{blow.penetration:.6g} m > L1 = {limits.L1:.6g} m (its head "
                           f"{blow.penetration - limits.L1:.4g} m below the soil face), still "
                           f"moving at {blow.v_pipe_end:.4g} m/s; {why}")
    if not blow.penetration >= -limits.rebound * (1.0 + _SLACK):
        raise DriveInvalid(f"blow {n}: penetration {blow.penetration:.6g} m, below the pipe's "
                           f"elastic rebound -{limits.rebound:.3g} m: blows push the pipe in")
