"""A whole drive through one FMU instance (or one core model): blow after blow until the target
or refusal.

Blow ``k`` (from 0) acts from ``t_k = k * period`` to ``t_k + duration``; its window ends where
the next blow starts, so the drive takes ``blows * period``. With a hammer (``spec.hammer``)
blow ``k`` is a strike of the ram at ``t_k`` (Q = 0; ``duration`` the contact's length). The
blow's edges are communication points (the FMU holds Q constant over a step). Inside the window the FMU is stepped:

* in steps of at most ``step`` while the blow acts and for a while after it (the blow's
  duration in the rigid model, a wave round trip 2 L1 / c1 in the elastic one), so that the
  peak velocities are seen (they are the largest values at the communication points). In the
  elastic model these steps are a whole number of its internal steps (``step`` rounded down,
  one at least): the FMU splits a communication step into equal internal steps no longer than
  courant dx / c, and on such steps the waves travel at the Courant number asked for (1: exact
  transport) instead of a smaller one;
* then, while the pipe still moves, in steps doubling in length;
* then in one step to the next blow, as soon as the motion has died out: ``at_rest`` (a step
  under Q = 0 leaves the whole state unchanged, so the model skips it without internal steps),
  or, in the elastic model, the front end and the plug beside it standing still for a wave
  round trip. The undamped elastic model rarely reaches ``at_rest`` before the whole pipe is in
  the soil: waves ring on in the part outside it (the pipe, with the plug stuck to it if the plug
  reaches there) and keep slipping a few cells of the pipe in the soil. The FMU still integrates
  them in that step; ``ringing_friction`` records the friction work they dissipate.

The state is never reset: every blow starts from the state the previous one left.

Clean-outs (``spec.cleanouts``): before a blow that is due one (by its number, or by the
penetration it starts at) the input ``cleanouts`` rises by one at the blow's start, as a strike
does; several due at once are one clean-out. A session without that input refuses the drive
(:func:`check_inputs`).

The plug (per blow): its length ``L2`` at the window's end (the output :data:`PLUG_LENGTH` when
the model has it, else the fixed L2), the incremental filling ratio IFR = dL2/ds over the blow
(from the length after a clean-out), the plug length ratio L2/s, and whether the soil cores into
the pipe (IFR > :data:`IFR_TOL`) or the pipe is plugged; a ratio whose denominator is 0 (a blow
that did not move the pipe; s <= 0) is not defined (``None``), never a number.
Without a plug (``tau2 = 0``, or ``L2 = 0`` without ``plug_growth``: :func:`no_plug`) none
of them is defined, and ``plugging`` is :data:`NO_PLUG`.

Stopping (checked after each blow, in this order): the front end has gone in by ``target``;
the blow did not move the front end at all (its set is exactly 0: static friction held it); the
last ``refusal_count`` blows advanced it by less than ``refusal_length`` in all; ``max_blows``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

from pipeplug import OUTPUT_NAMES, OUTPUTS, PARAMETERS, Outputs
from pipeplug.interface import LEDGER_SOURCES, LEDGER_TERMS
from pipeplug_harness.errors import UserError
from pipeplug_harness.session import CoreSession, FmuSession, Session

from .checks import Limits, check_blow
from .file import DriveSpec

__all__ = ["Blow", "DriveResult", "run_drive", "run_drive_on_core", "drive_with", "OUTCOMES",
           "PLUG_LENGTH", "IFR_TOL", "WORKS", "CLEANOUT_INPUT", "NO_PLUG", "check_inputs",
           "no_plug"]

#: outcome -> what it means (the summary's words)
OUTCOMES = {
    "target": "target reached",
    "static": "refusal: a blow did not move the pipe (static friction)",
    "set": "refusal: set below the threshold",
    "max_blows": "stopped at max_blows, no refusal",
}

#: the output giving the plug's current length [m], when the model has it (a growing plug)
PLUG_LENGTH = "L2_now"
#: the input whose rise cleans the plug out, and the parameter the plug is cleaned down to
CLEANOUT_INPUT, CLEANOUT_LENGTH = "cleanouts", "L2_after_cleanout"
#: IFR above this is coring (soil enters the pipe as it advances); at or below, plugged. The
#: plug's lengths are exact to round-off (a few ulps of L2 over a set of at least 1e-9 of it),
#: so any growth the model makes shows; a plug that does not grow reads 0 exactly.
IFR_TOL = 1e-6
#: the ``plugging`` of every blow of a drive without a plug (:func:`no_plug`)
NO_PLUG = "no plug"
#: the works of the ledger reported per blow beside W_input and friction's two parts: every
#: other work, by the ledger's table (so that the works of effects added later are reported)
WORKS = tuple(n for n in LEDGER_SOURCES + LEDGER_TERMS
              if n.startswith("W_") and n not in ("W_input", "W_friction"))

#: the outputs at t = 0: at rest, nothing moved, no work done
_ZERO = Outputs(*(True if o.kind == "Boolean" else 0 if o.kind == "Integer" else 0.0
                  for o in OUTPUTS))


@dataclass
class Blow:
    """One blow's record: increments over its window, peaks, and the state at its end (SI)."""

    blow: int                 #: 1, 2, ...
    t_start: float            #: [s]
    set: float                #: penetration gained over the window [m]
    penetration: float        #: front-end displacement at the window's end [m]
    v_pipe_peak: float        #: largest pipe velocity at the window's points [m/s]
    v_plug_peak: float        #: largest plug velocity at the window's points [m/s]
    W_input: float            #: work of Q over the window [J]
    W_friction_outer: float   #: [J]
    W_friction_inner: float   #: [J]
    v_pipe_end: float         #: [m/s]
    v_plug_end: float         #: [m/s]
    settled: str              #: "rest" (at_rest), "front" (front end still) or "moving"
    motion: float             #: from the blow's start to the first point found still (settled) [s]
    steps: int                #: communication steps of the window
    ringing_friction: float   #: friction work [J] dissipated after the front end stopped for
                              #: good (0 when it still moved at the window's end)
    stress_head_min: float    #: most compressive axial stress at the head, at the window's
                              #: points [Pa] (compression negative)
    stress_head_max: float    #: most tensile one there [Pa]
    stress_min: float         #: most compressive axial stress anywhere along the pipe over the
                              #: window [Pa] (elastic: over every internal step)
    stress_max: float         #: most tensile one [Pa]
    enthru: float             #: energy through the head over the window, the integral of
                              #: F_head times the head's velocity (ENTHRU) [J]
    enthru_share: float | None  #: ENTHRU over the hammer's rated energy [1] (None: not
                                #: defined, no hammer)
    cleanout: bool            #: the plug was cleaned out at the blow's start
    L2: float | None          #: plug length at the window's end [m] (None: no plug)
    ifr: float | None         #: incremental filling ratio dL2/ds over the blow [1] (None: not
                              #: defined, the blow did not move the pipe, or no plug)
    plr: float | None         #: plug length ratio L2/s at the window's end [1] (None: s <= 0,
                              #: or no plug)
    plugging: str             #: "coring" (ifr > IFR_TOL), "plugged", "" (ifr not defined) or
                              #: :data:`NO_PLUG`
    metres_per_hour: float    #: the blow's set at the blow rate: set x blows/min x 60 [m/h]
    works: dict               #: :data:`WORKS` over the window [J] by name


@dataclass
class DriveResult:
    spec: DriveSpec
    blows: list = field(default_factory=list)
    outcome: str = ""
    steps: int = 0            #: communication steps of the whole drive

    @property
    def penetration(self) -> float:
        return self.blows[-1].penetration if self.blows else 0.0

    @property
    def drive_time(self) -> float:
        """Drive time at the blow rate [s]: blows x period."""
        return len(self.blows) * self.spec.period

    @property
    def metres_per_hour(self) -> float | None:
        """Penetration over the drive time at the blow rate [m/h] (None: no blow)."""
        return 3600.0 * self.penetration / self.drive_time if self.blows else None

    @property
    def cleanouts(self) -> int:
        """Clean-outs made."""
        return sum(b.cleanout for b in self.blows)


def run_drive(spec: DriveSpec, fmu, progress=None) -> DriveResult:
    """Drive the pipe blow by blow through one instance of the FMU ``fmu``."""
    with FmuSession(fmu, spec.start_values, name="drive") as session:
        return drive_with(spec, session, progress)


def run_drive_on_core(spec: DriveSpec, progress=None) -> DriveResult:
    """Drive the pipe blow by blow through one core model (no FMU: the same model, stepped as
    the FMU steps it)."""
    with CoreSession(spec.start_values) as session:
        return drive_with(spec, session, progress)


def drive_with(spec: DriveSpec, session: Session, progress=None) -> DriveResult:
    """Drive the pipe blow by blow through ``session`` (an instance at t = 0, at rest).

    Every blow is checked (:func:`pipeplug_harness.drive.checks.check_blow`): a violation
    raises :class:`~pipeplug_harness.drive.checks.DriveInvalid` and no result is returned.
    ``progress(blow)`` is called after each blow (its :class:`Blow`).
    """
    check_inputs(spec, session.inputs)
    result = DriveResult(spec)
    pace = _pace(spec)
    limits = Limits.of(spec)
    before, plug, done = _ZERO, _Plug.of(spec), 0
    for k in range(spec.max_blows):
        due = spec.cleanouts.passed(k + 1, before.u_pipe) if spec.cleanouts else 0
        blow, before, pushed = _blow(session, spec, k, before, pace, plug, due > done)
        done = due
        check_blow(limits, blow, before, (k + 1) * spec.period, session.steps, pushed)
        result.blows.append(blow)
        if progress is not None:
            progress(blow)
        result.outcome = _verdict(spec, result.blows)
        if result.outcome:
            break
    else:
        result.outcome = "max_blows"
    result.steps = session.steps
    return result


class _Pace(NamedTuple):
    step: float      #: the fine communication step [s]
    fine: float      #: fine steps for this long after the blow [s]
    settle: float    #: the front end still this long: the motion has died out [s]
    grain: float     #: the elastic model's internal step [s] (0: rigid)


def _pace(spec: DriveSpec) -> _Pace:
    if not spec.elastic:
        return _Pace(spec.step, spec.duration, math.inf, 0.0)
    from pipeplug.elastic.grid import build_grid
    p = spec.params()
    grain = build_grid(p).h_max
    round_trip = 2.0 * p.L1 / p.c1
    return _Pace(grain * max(1, math.floor(spec.step / grain + 1e-9)), round_trip, round_trip,
                 grain)


def _blow_points(t0: float, duration: float, pace: _Pace) -> list:
    """The communication points of a blow after ``t0``, its end last.

    Rigid: equal steps of at most ``pace.step``. Elastic: steps of ``pace.step``, a whole
    number of internal steps (so that waves travel at the Courant number asked for), and the
    remainder.
    """
    t_end = t0 + duration
    if not pace.grain:
        n = max(1, math.ceil(duration / pace.step - 1e-9))
        return [t0 + duration * i / n for i in range(1, n)] + [t_end]
    m = math.floor(duration / pace.step + 1e-9)
    points = [t0 + i * pace.step for i in range(1, m + 1)]
    if points and t_end - points[-1] <= 1e-9 * pace.step:
        points[-1] = t_end
    else:
        points.append(t_end)
    return points


def check_inputs(spec: DriveSpec, inputs) -> None:
    """Refuse a drive that needs an input the FMU (or model) does not have: clean-outs need
    :data:`CLEANOUT_INPUT`.

    Raises
    ------
    UserError
        Naming the drive file's key, its values and the inputs there are.
    """
    if spec.cleanouts is not None and CLEANOUT_INPUT not in inputs:
        raise UserError(key=spec.cleanouts.key, value=list(spec.cleanouts.at),
                        allowed=f"none with this FMU: it has no input {CLEANOUT_INPUT!r} (a "
                                f"plug that grows and is cleaned out); its inputs: "
                                f"{', '.join(sorted(inputs))}")


def no_plug(spec: DriveSpec) -> str:
    """Why the drive has no plug ("": it has one): ``tau2 = 0`` (no friction couples soil in the
    pipe to it) or ``L2 = 0`` without ``plug_growth`` (docs/files.md: "tau2 = 0 or L2 = 0: no
    plug"; a plug that grows may start empty)."""
    p = spec.params()
    if not p.tau2 > 0.0:
        return "tau2 = 0"
    if not p.L2 > 0.0 and not spec.start_values.get("plug_growth", False):
        return "L2 = 0"
    return ""


class _Plug:
    """The plug's length: read from the outputs, or fixed; and where a clean-out leaves it.
    Without a plug (:func:`no_plug`) every plug measure is not defined."""

    def __init__(self, initial: float, after_cleanout: float, present: bool = True):
        self.present = present
        self.length = (lambda out: getattr(out, PLUG_LENGTH)) if PLUG_LENGTH in OUTPUT_NAMES \
            else (lambda out: initial)
        self.initial, self.after_cleanout = initial, after_cleanout
        self.last = initial                   # at the last blow's end [m]

    @classmethod
    def of(cls, spec: DriveSpec) -> _Plug:
        defaults = {p.name: p.default for p in PARAMETERS}
        after = spec.start_values.get(CLEANOUT_LENGTH, defaults.get(CLEANOUT_LENGTH, 0.0))
        return cls(spec.params().L2, after, not no_plug(spec))

    def blow(self, out: Outputs, cleaned: bool, moved: float, penetration: float) -> tuple:
        """``(L2, ifr, plr, plugging)`` of a blow ending at ``out`` (the clean-out at its start
        leaves at most ``after_cleanout``)."""
        if not self.present:
            return None, None, None, NO_PLUG
        start = min(self.last, self.after_cleanout) if cleaned else self.last
        self.last = length = self.length(out)
        ifr = (length - start) / moved if moved != 0.0 else None
        plr = length / penetration if penetration > 0.0 else None
        label = "" if ifr is None else "coring" if ifr > IFR_TOL else "plugged"
        return length, ifr, plr, label


def _blow(s: Session, spec: DriveSpec, k: int, before: Outputs, pace: _Pace, plug: _Plug,
          cleaned: bool) -> tuple[Blow, Outputs, float]:
    """Blow ``k`` and the motion after it, up to the next blow's start (the plug cleaned out
    at its start when ``cleaned``); the last value is the penetration [m] when the blow stopped
    acting (``duration`` after its start)."""
    t0, h, t_next = k * spec.period, pace.step, (k + 1) * spec.period
    steps0 = s.steps
    peaks = [before.v_pipe, before.v_plug, math.inf, -math.inf, math.inf, -math.inf]
    t = t0
    if cleaned:
        s.cleanout()
    if spec.hammer is not None:
        s.strike(spec.hammer.v_strike)
    for tb in _blow_points(t0, spec.duration, pace):
        out = s.step(t, tb - t, spec.amplitude)
        t = tb
        _raise(peaks, out)
    pushed = out.u_pipe
    settled, motion, still_since, fine_until = "moving", spec.period, None, t + pace.fine
    w_still = 0.0                                     # friction work when the front end stopped
    while t < t_next:
        if out.at_rest or (still_since is not None and t - still_since >= pace.settle):
            settled, motion = ("rest", t - t0) if out.at_rest else ("front", still_since - t0)
            out = s.step(t, t_next - t, 0.0)          # no internal steps when at rest
            break
        if t >= fine_until:
            h *= 2.0
        tb = t + h if t_next - (t + h) > 0.5 * h else t_next
        if t < t_next - pace.settle < tb:
            # a point a settling window before the next blow: a front end still there and at
            # the window's end has settled (the growing steps would skip it otherwise, and a
            # pipe still for most of the period would end it "moving")
            tb = t_next - pace.settle
        out = s.step(t, tb - t, 0.0)
        t = tb
        if out.v_pipe == 0.0 and out.v_plug == 0.0:
            if still_since is None:
                still_since, w_still = t, _friction(out)
        else:
            still_since = None
        _raise(peaks, out)
    else:                                             # the window's last step: as at the top
        if out.at_rest or (still_since is not None and t - still_since >= pace.settle):
            settled, motion = ("rest", t - t0) if out.at_rest else ("front", still_since - t0)
    moved = out.u_pipe - before.u_pipe
    blow = Blow(k + 1, t0, moved, out.u_pipe, peaks[0], peaks[1],
                out.W_input - before.W_input, out.W_friction_outer - before.W_friction_outer,
                out.W_friction_inner - before.W_friction_inner, out.v_pipe, out.v_plug,
                settled, motion, s.steps - steps0,
                0.0 if still_since is None else _friction(out) - w_still, *peaks[2:],
                out.E_transferred - before.E_transferred,
                (out.E_transferred - before.E_transferred) / spec.hammer.rated_energy
                if spec.hammer is not None else None,
                cleaned, *plug.blow(out, cleaned, moved, out.u_pipe), 3600.0 * moved / spec.period,
                {n: getattr(out, n) - getattr(before, n) for n in WORKS})
    return blow, out, pushed


def _friction(out: Outputs) -> float:
    """Friction work dissipated since t = 0 [J]."""
    return out.W_friction_outer + out.W_friction_inner


def _raise(peaks: list, out: Outputs) -> None:
    """Keep the largest velocities and the extreme stresses (head, along the pipe)."""
    peaks[0] = max(peaks[0], out.v_pipe)
    peaks[1] = max(peaks[1], out.v_plug)
    peaks[2] = min(peaks[2], out.stress_head)
    peaks[3] = max(peaks[3], out.stress_head)
    peaks[4] = min(peaks[4], out.stress_min)
    peaks[5] = max(peaks[5], out.stress_max)


def _verdict(spec: DriveSpec, blows: list) -> str:
    """The outcome after the last blow, or "" to go on."""
    last = blows[-1]
    if last.penetration >= spec.target:
        return "target"
    if last.set == 0.0:
        return "static"
    n = spec.refusal_count
    if len(blows) >= n and sum(b.set for b in blows[-n:]) < spec.refusal_length:
        return "set"
    return ""
