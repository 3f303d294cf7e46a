"""Scene files: one job described in TOML (the sections of :data:`pipeplug_harness.spec.SCENE`)::

    [pipe]                      # L1 (required) R1 h1 rho1 E1
    L1 = "1 m"
    [plug]                      # L2 tau2 (required) rho2 E2   (tau2 = 0 or L2 = 0: no plug)
    L2 = 1.0
    tau2 = "10 kPa"
    [soil]                      # tau1 (required) contact_growth
    tau1 = 2.0e4
    [blows]                     # amplitude, duration (required); period or rate, count, start
    amplitude = "23 kN"
    duration = "50 ms"
    # or, instead of [blows], the strikes of a ram (PipePlug's own, through its inputs):
    # [hammer]                  # rated_energy, ram_mass, rate (required); efficiency,
    #                           # cushion_stiffness, cushion_restitution, count, start
    [model]                     # elastic = true | false | "auto"; solver; dt dx courant x_monitor
    elastic = "auto"
    [output]                    # stop_time, step, variables
    stop_time = 0.3
    [checks]                    # allow = ["R1"]: keys allowed outside their plausible range
    allow = []

Values are SI numbers or strings with units. Unknown sections, keys or values, missing required
sections or keys, implausible values and values the core refuses (L2 > L1, say) are errors
naming the file, the key, the value and what is allowed, before any output is written. The
blows follow the Hammer FMU's rules (:mod:`pipeplug_harness.spec.blows`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from pipeplug.params import ParameterError
from pipeplug_harness import spec
from pipeplug_harness.core_check import check_with_core
from pipeplug_harness.errors import UserError
from pipeplug_harness.limits import Limits
from pipeplug_harness.load import Load
from pipeplug_harness.session import split_start_values

__all__ = ["Scene", "load_scene", "scene_of", "AFTER_BLOWS"]

#: without a stop time a scene runs this long after its last blow ends [s]
AFTER_BLOWS = 0.25


@dataclass
class Scene:
    """A validated scene: FMU start values, the load, output settings, why it is (not)
    elastic."""

    name: str
    start_values: dict
    load: Load
    stop_time: float
    step: float
    variables: list
    reason: str = ""
    strikes: tuple = ()      #: (time [s], ram velocity [m/s]) of each strike

    @property
    def steps(self) -> int:
        """Communication steps of the run."""
        return math.ceil(self.stop_time / self.step - 1e-9)


def load_scene(path, limits: Limits | None = None) -> Scene:
    """Read, validate and bound a scene file (errors name the file)."""
    path = Path(path)
    try:
        return scene_of(path.stem, spec.read_file(path, spec.SCENE), limits or Limits())
    except UserError as exc:
        raise exc.in_file(path) from None


def scene_of(name: str, values: dict, limits: Limits) -> Scene:
    """A :class:`Scene` from checked sections (:func:`pipeplug_harness.spec.checked`)."""
    blows, hammer, output = values.pop("blows"), values.pop("hammer"), values.pop("output")
    values.pop("checks")
    section, train = _train(blows, hammer)
    stop = output["stop_time"]
    if stop is None:
        if not train.count:
            raise UserError(f"[output] stop_time is missing: a train without end ([{section}] "
                            f"count = 0) runs to the stop time")
        stop = train.end() + AFTER_BLOWS
    count = train.count or math.ceil((stop - train.start) / train.period)
    limits.check("blows", count, f"[{section}] count = {train.count} over [output] stop_time "
                                 f"= {stop!r} s")
    step = output["step"]
    steps = stop / step
    limits.check("steps", steps, f"[output] step = {step!r} s to stop_time = {stop!r} s")
    limits.memory(steps * (1 + len(output["variables"])), f"recording {len(output['variables'])}"
                                                          f" variables every {step!r} s")
    strikes = ()
    if section == "hammer":
        values.update(ram_mass=train.ram_mass, cushion_stiffness=hammer["cushion_stiffness"],
                      cushion_restitution=hammer["cushion_restitution"])
        strikes = tuple((train.start + k * train.period, train.v_strike) for k in range(count)
                        if train.start + k * train.period < stop)
        # the elastic rule compares the strike's contact with the wave round trip: the
        # cushion's half period on a fixed head (a direct strike: immediate)
        k = hammer["cushion_stiffness"]
        duration = math.pi * math.sqrt(train.ram_mass / k) if k > 0.0 else 0.0
        load = Load()
    else:
        duration, load = train.duration, Load.from_train(train, stop)
    choice = values.pop("elastic")
    elastic, reason = spec.elastic_choice(choice, values, duration)
    reason += spec.unused_model_keys(choice, values, elastic)
    start_values = {k: v for k, v in values.items() if v is not None}
    start_values["elastic"] = elastic
    try:                  # the core's own rules now, not the FMU's refusal after the folder
        check_with_core(start_values)
    except ParameterError as exc:
        raise UserError(str(exc)) from None
    if elastic:
        _bound_elastic(start_values, stop, limits)
    return Scene(name, start_values, load, stop, step, list(output["variables"]), reason,
                 strikes)


def _train(blows: dict, hammer: dict):
    """("blows", the blow train) or ("hammer", the strikes), exactly one of them given."""
    if hammer["rated_energy"] is None:
        if blows["amplitude"] is None:
            raise UserError("missing section [blows] or [hammer]: a scene needs one (keys of "
                            "[blows]: amplitude, duration, ...; of [hammer]: rated_energy, "
                            "ram_mass, rate, ...)")
        return "blows", spec.blow_train(blows)
    if blows["amplitude"] is not None:
        raise UserError("[blows] and [hammer] both given; allowed: one of them (rectangular "
                        "blows of a force, or the strikes of a ram)")
    return "hammer", spec.ram_train(hammer, hammer["count"], hammer["start"])


def _bound_elastic(start_values: dict, stop: float, limits: Limits) -> None:
    """Refuse an elastic run whose cells x internal steps pass the work limit."""
    from pipeplug.params import Params
    try:
        p = Params.from_mapping(split_start_values(start_values)[0])
    except ParameterError as exc:
        raise UserError(str(exc)) from None
    if not (p.dx > 0.0 and p.E1 > 0.0 and p.rho1 > 0.0 and p.courant > 0.0):
        return                                 # the core refuses these with its own words
    speed = max(p.c1, p.c2 if p.E2 > 0.0 and p.rho2 > 0.0 else 0.0)
    cells = (p.L1 + p.L2) / p.dx
    internal = stop * speed / (p.courant * p.dx)
    limits.check("work", cells * internal, f"the elastic model ({cells:.3g} cells of dx = "
                                           f"{p.dx!r} m, {internal:.3g} internal steps)")
