"""Drive files: a whole drive described in TOML (:data:`pipeplug_harness.spec.DRIVE`).

A drive file has the scene sections ``[pipe]``, ``[plug]``, ``[soil]``, ``[blows]`` and ``[model]``
(same keys, units and rules, see :mod:`pipeplug_harness.scene.file`) with these differences, and
a ``[drive]`` section::

    [soil]          tau1; contact_growth may only be true (the pipe starts at the soil face:
                    model II, penetration 0, no outer contact)
    [blows]         amplitude [N] > 0, duration [s], period [s] > duration, or rate (no count,
                    no start: blow k starts at k * period)
    [hammer]        instead of [blows], the hammer by its ram: rated_energy [J], efficiency
                    (default 1), ram_mass [kg], rate [1/s] ("200 /min"), cushion_stiffness
                    [N/m] (default 0: a direct strike), cushion_restitution (default 1);
                    strike k starts at k / rate with the ram at v = sqrt(2 efficiency
                    rated_energy / ram_mass) (PipePlug's ram; Q = 0)
    [model]         elastic = true | false | "auto"; solver dt dx courant (no x_monitor: the
                    drive monitors the pipe's front end, whose displacement is the penetration);
                    without dx, the elastic model takes the coarsest grid of at least
                    GRID_CELLS cells along the pipe and GRID_CELLS along the blow's wave c1 td
                    whose cells fit L1 and L2 a whole number of times (:func:`grid_for`)
    [drive]
    target = 30.0           # [m] stop when the front end has gone in this far (default and
                            #     at most L1)
    refusal_set = 1e-4      # [m] refusal: a blow whose set is below this, or
    refusal_count = 10      #     refusal_count blows that together advance the pipe less
    refusal_length = 0.025  #     than refusal_length [m] (default: 10 blows per 25 mm)
    max_blows = 100000      # stop after this many blows
    yield_stress = 2.41e8   # [Pa] the pipe's yield: the summary states the largest stress
                            #     against it (optional)
    step = 1e-4             # [s] communication step while the blow acts and just after it
                            #     (default: duration / 10; elastic: rounded down to whole
                            #     internal steps, see pipeplug_harness.drive.run)
    cleanout_at = ["2 m", "4.5 m"]   # clean the plug out before the first blow at or past
                            #     each penetration [m], or
    cleanout_at_blows = [300, 600]   # before each of these blows (not both; ascending):
                            #     the FMU's input cleanouts rises by one there (an FMU without
                            #     that input refuses the drive)

``refusal_set = 0`` turns the set refusal off and leaves only the other refusal: a blow that
does not move the front end at all (static friction holds it); the summary says so.
``refusal_length`` must be > 0 (refusal_count blows advancing less than 0 m would never
refuse). Unknown sections, keys or values are errors naming the allowed ones; every parameter is
then checked by the core itself (:func:`check_with_core`).
"""
from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

from pipeplug_harness import spec as files
from pipeplug_harness.core_check import check_with_core
from pipeplug_harness.core_check import params_of as _params
from pipeplug_harness.errors import UserError
from pipeplug_harness.limits import Limits

__all__ = ["DriveSpec", "Hammer", "Cleanouts", "DEFAULT_REFUSAL", "GRID_CELLS", "load_drive", "drive_spec",
           "check_with_core", "grid_for"]

#: The default refusal of pile-driving practice: 10 blows per 25 mm.
DEFAULT_REFUSAL = (10, 0.025)
#: Without dx: at least this many cells along the pipe and along the blow's wave c1 td.
GRID_CELLS = 20
_GRID_TRIES = 10_000             # cell counts tried for one that fits L2 too


@dataclass(frozen=True)
class Hammer:
    """A drive's hammer by its ram (SI): the strike's velocity and what it comes from."""

    rated_energy: float      #: [J]
    efficiency: float        #: [1]
    ram_mass: float          #: [kg]
    v_strike: float          #: sqrt(2 efficiency rated_energy / ram_mass) [m/s]


@dataclass(frozen=True)
class Cleanouts:
    """When a drive cleans the plug out: before the first blow that starts at or past each
    penetration of ``at`` [m] (``by = "penetration"``), or before each blow numbered in ``at``
    (``by = "blow"``); ascending."""

    by: str                  #: "penetration" or "blow"
    at: tuple                #: penetrations [m] or blow numbers (1, 2, ...)

    @property
    def key(self) -> str:
        """The drive file's key that gave them."""
        return "[drive] cleanout_at" + ("_blows" if self.by == "blow" else "")

    def passed(self, blow: int, penetration: float) -> int:
        """How many clean-outs are due before blow ``blow`` (1, 2, ...) starting at
        ``penetration`` [m]: the values reached so far."""
        return bisect.bisect_right(self.at, blow if self.by == "blow" else penetration)


@dataclass(frozen=True)
class DriveSpec:
    """A validated drive: FMU start values, the blow train and the stopping rules.

    ``refusal_count`` blows advancing the pipe less than ``refusal_length`` [m] in all is a
    refusal (a set per blow threshold is ``refusal_count = 1``).
    """

    name: str
    start_values: dict       #: FMU start values (parameters and options), contract names, SI
    amplitude: float         #: [N]
    duration: float          #: [s]
    period: float            #: [s]
    target: float            #: [m]
    refusal_count: int
    refusal_length: float    #: [m]
    max_blows: int
    step: float              #: [s]
    reason: str              #: why the model is (not) elastic
    grid: str = ""           #: the elastic model's grid and where dx came from
    hammer: Hammer | None = None   #: the blows are strikes of this ram (amplitude 0)
    yield_stress: float | None = None    #: [Pa]
    cleanouts: Cleanouts | None = None   #: when the plug is cleaned out (None: never)

    @property
    def elastic(self) -> bool:
        return bool(self.start_values["elastic"])

    def params(self):
        """The core's :class:`~pipeplug.params.Params` of this drive."""
        return _params(self.start_values)

    def refusal_text(self) -> str:
        if self.refusal_count == 1:
            return f"set < {self.refusal_length:g} m per blow"
        return f"{self.refusal_count} blows advance < {self.refusal_length:g} m"


def load_drive(path, limits: Limits | None = None) -> DriveSpec:
    """Read, validate, check with the core and bound a drive file (errors name the file)."""
    path = Path(path)
    try:
        return drive_spec(path.stem, files.read_file(path, files.DRIVE), limits)
    except ValueError as exc:                 # UserError, or the core's ParameterError
        raise _in_file(exc, path) from None


def _in_file(exc: ValueError, path) -> UserError:
    if isinstance(exc, UserError):
        return exc.in_file(path)
    return UserError(str(exc), file=path)


def drive_spec(name: str, values: dict, limits: Limits | None = None) -> DriveSpec:
    """A :class:`DriveSpec` from checked sections (``values`` as :func:`pipeplug_harness.spec.
    checked` gives them: ``blows`` and ``drive`` nested, the rest flat).

    The blows follow the one rule set of blow trains, and a drive's own: they push (amplitude >
    0), and each leaves the pipe a while before the next (period > duration).
    """
    blows, given, drive = values.pop("blows"), values.pop("hammer"), values.pop("drive")
    values.pop("checks", None)
    if values["contact_growth"] is not True:
        raise UserError("[soil] contact_growth = false; allowed: true (a drive starts at the "
                        "soil face: model II, outer friction over the penetrated length)")
    hammer = _hammer(given, blows)
    if hammer is None:
        train = _rectangular(blows)
    else:
        train = _strikes(hammer, given, values)
        values.update(ram_mass=hammer.ram_mass, cushion_stiffness=given["cushion_stiffness"],
                      cushion_restitution=given["cushion_restitution"])
    choice = values.pop("elastic")
    elastic, reason = files.elastic_choice(choice, values, train.duration)
    reason += files.unused_model_keys(choice, values, elastic)
    start = {k: v for k, v in values.items() if v is not None}
    start["elastic"] = elastic
    grid = ""
    if elastic:                                      # monitor the front end: penetration
        start["x_monitor"] = _params(start).L1
        if "dx" not in start:
            start["dx"], grid = grid_for(_params(start), train.duration)
        else:
            grid = "dx given"
    params = check_with_core(start)
    L1 = params.L1
    if elastic:
        grid = _grid_text(params, grid)
    target = L1 if drive["target"] is None else drive["target"]
    if not 0.0 < target <= L1:
        raise UserError(f"[drive] target = {target!r} m; allowed: > 0 and <= L1 = {L1!r} m")
    count, length = _refusal(drive)
    step = train.duration / 10.0 if drive["step"] is None else drive["step"]
    for key, value, ok, allowed in (("max_blows", drive["max_blows"], drive["max_blows"] >= 1,
                                     ">= 1"),
                                    ("step", step, step > 0.0 and math.isfinite(step), "> 0")):
        if not ok:
            raise UserError(f"[drive] {key} = {value!r}; allowed: {allowed}")
    _bound(limits or Limits(), params, elastic, train, step, drive["max_blows"])
    cleanouts = _cleanouts(drive)
    if cleanouts is not None and not start.get("plug_growth", False):
        raise UserError(f"[drive] cleanout_{'at' if cleanouts.by == 'penetration' else 'at_blows'}"
                        f" = {list(cleanouts.at)!r}; allowed: none without [plug] "
                        f"plug_growth = true (only a plug that grows is cleaned out)")
    return DriveSpec(name, start, train.amplitude, train.duration, train.period,
                     target, count, length, drive["max_blows"], step, reason, grid, hammer,
                     drive["yield_stress"], cleanouts)


class _Train(NamedTuple):
    amplitude: float     #: [N]
    duration: float      #: the blow's, or the strike's contact time [s]
    period: float        #: [s]


def _rectangular(blows: dict) -> _Train:
    """The rectangular blows of [blows]: they push (amplitude > 0), and each leaves the pipe
    a while before the next (period > duration)."""
    if blows["amplitude"] is None:
        raise UserError("missing section [blows] or [hammer]: a drive needs one (keys of "
                        "[blows]: amplitude, duration, period or rate; of [hammer]: "
                        "rated_energy, efficiency, ram_mass, rate, cushion_stiffness, "
                        "cushion_restitution)")
    period = files.period_of(blows)
    if not period > blows["duration"]:
        raise UserError(f"[blows] period = {period!r} s; allowed: > duration "
                        f"({blows['duration']!r} s)")
    train = files.blow_train({**blows, "count": 0})
    if not train.amplitude > 0.0:
        raise UserError(f"[blows] amplitude = {train.amplitude!r} N; allowed: > 0 (a blow "
                        f"drives the pipe into the soil)")
    return _Train(train.amplitude, train.duration, train.period)


def _hammer(given: dict, blows: dict) -> Hammer | None:
    """The [hammer] of a drive (None without one), by the Hammer's rules
    (:func:`pipeplug_harness.spec.ram_train`); never with [blows]."""
    if given["rated_energy"] is None:
        return None
    if blows["amplitude"] is not None:
        raise UserError("[blows] and [hammer] both given; allowed: one of them (rectangular "
                        "blows of a force, or the strikes of a ram)")
    train = files.ram_train(given)
    return Hammer(given["rated_energy"], given["efficiency"], train.ram_mass, train.v_strike)


def _strikes(hammer: Hammer, given: dict, values: dict) -> _Train:
    """The strike train: Q = 0, one strike every 1 / rate; its "duration" the contact's
    length, for the fine steps and the elastic grid: the cushion's half period on a fixed
    head, pi sqrt(m / k), or, struck directly, three times the exponential pulse's m / Z1 on
    an elastic pipe (m / Z1 of the rigid limit's impulse is 0: a tenth of the period then)."""
    period = 1.0 / given["rate"]
    k = given["cushion_stiffness"]
    if k > 0.0:
        contact = math.pi * math.sqrt(hammer.ram_mass / k)
    else:
        p = _params({k: v for k, v in values.items() if v is not None and k != "elastic"})
        contact = 3.0 * hammer.ram_mass / (p.S1 * math.sqrt(p.E1 * p.rho1))
    contact = min(contact, 0.1 * period)
    return _Train(0.0, contact, period)


def _bound(limits: Limits, params, elastic: bool, train, step: float, max_blows: int) -> None:
    """Refuse a drive whose blows would take more steps or work than the limits allow."""
    limits.check("blows", max_blows, f"[drive] max_blows = {max_blows}")
    limits.check("steps", train.duration / step, f"[drive] step = {step!r} s over a blow of "
                                                 f"{train.duration!r} s")
    if elastic:
        from pipeplug.elastic.grid import build_grid
        g = build_grid(params)
        limits.check("work", (g.n1 + g.n2) * train.period / g.h_max,
                     f"each blow's window of the elastic model ({g.n1 + g.n2} cells, "
                     f"{train.period / g.h_max:.3g} internal steps)")


def grid_for(params, duration: float) -> tuple[float, str]:
    """The drive's default dx [m] and how it was chosen: the fewest cells ``n >= GRID_CELLS``
    and ``>= GRID_CELLS L1 / (c1 td)`` (the blow's wave, ``td = duration`` [s], at least
    GRID_CELLS cells long) for which ``L2 n / L1`` is whole when the plug is simulated.

    Raises
    ------
    UserError
        When no such count is found among the next few thousand (L2 / L1 not a ratio of small
        integers): the file must give dx.
    """
    p = params
    wave = p.c1 * duration
    least = max(GRID_CELLS, math.ceil(GRID_CELLS * p.L1 / wave - 1e-9))
    for n in range(least, least + _GRID_TRIES):
        plug_cells = p.L2 * n / p.L1
        if not p.has_plug or abs(plug_cells - round(plug_cells)) <= 1e-9 * max(1.0, plug_cells):
            return p.L1 / n, (f"dx chosen: the fewest cells >= {GRID_CELLS} along the pipe and "
                              f">= {GRID_CELLS} along the blow's wave c1 td = {wave:.4g} m that "
                              f"fit L1 and L2")
    raise UserError(f"[model] no dx given, and no grid of {least} to {least + _GRID_TRIES - 1} "
                     f"cells fits both L1 = {p.L1!r} m and L2 = {p.L2!r} m; give dx (a length "
                     f"that divides both)")


def _grid_text(params, how: str) -> str:
    """The elastic grid in words: cells, dx, internal step."""
    from pipeplug.elastic.grid import build_grid
    g = build_grid(params)
    plug = f" and {g.n2} plug cells" if g.n2 else ""
    return (f"model III grid: {g.n1} pipe cells{plug} of dx = {params.dx:.6g} m ({how}), "
            f"internal step {g.h_max:.4g} s")


def _refusal(drive: dict) -> tuple[int, float]:
    """(count, length) of the set refusal from either form in [drive]."""
    per_blow = drive["refusal_set"]
    count, length = drive["refusal_count"], drive["refusal_length"]
    if per_blow is not None and (count is not None or length is not None):
        raise UserError("[drive] give either refusal_set, or refusal_count and refusal_length "
                         "(blows per length), not both")
    if per_blow is not None:
        count, length = 1, per_blow
    elif count is None and length is None:
        count, length = DEFAULT_REFUSAL
    elif count is None or length is None:
        raise UserError("[drive] refusal_count and refusal_length go together (blows per "
                         "length)")
    if count < 1:
        raise UserError(f"[drive] refusal_count = {count!r}; allowed: >= 1")
    if per_blow is not None:
        if not (per_blow >= 0.0 and math.isfinite(per_blow)):
            raise UserError(f"[drive] refusal_set = {per_blow!r} m; allowed: >= 0 (0: no set "
                            f"refusal, only a blow that does not move the pipe is one)")
    elif not (length > 0.0 and math.isfinite(length)):
        # refusal_count blows advancing "less than 0 m" would never refuse: a set refusal
        # silently off. refusal_set = 0 is how a file says so.
        raise UserError(f"[drive] refusal_length = {length!r} m; allowed: > 0 (for no set "
                        f"refusal, refusal_set = 0)")
    return count, length


def _cleanouts(drive: dict) -> Cleanouts | None:
    """The clean-outs of [drive] (None: none), by penetration or by blow, not both."""
    at, blows = drive["cleanout_at"], drive["cleanout_at_blows"]
    if at is not None and blows is not None:
        raise UserError(f"[drive] cleanout_at = {list(at)!r} m and cleanout_at_blows = "
                        f"{list(blows)!r} both given; allowed: one of them (clean-outs by "
                        f"penetration or by blow number)")
    if at is None and blows is None:
        return None
    return Cleanouts("penetration", at) if at is not None else Cleanouts("blow", blows)
