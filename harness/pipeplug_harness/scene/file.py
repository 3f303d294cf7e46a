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
    [model]                     # elastic = true | false | "auto"; solver; dt dx courant x_monitor
    elastic = "auto"
    [output]                    # stop_time, step, variables
    stop_time = 0.3
    [checks]                    # allow = ["R1"]: keys allowed outside their plausible range
    allow = []

Values are SI numbers or strings with units. Unknown sections, keys or values, missing required
sections or keys, and implausible values are errors naming the file, the key, the value and what
is allowed. The blows follow the Hammer FMU's rules (:mod:`pipeplug_harness.spec.blows`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from pipeplug_harness import spec
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
    blows, output = values.pop("blows"), values.pop("output")
    values.pop("checks")
    train = spec.blow_train(blows)
    stop = output["stop_time"]
    if stop is None:
        if not train.count:
            raise UserError("[output] stop_time is missing: a train without end ([blows] "
                            "count = 0) runs to the stop time")
        stop = train.end() + AFTER_BLOWS
    count = train.count or math.ceil((stop - train.start) / train.period)
    limits.check("blows", count, f"[blows] count = {train.count} over [output] stop_time = "
                                 f"{stop!r} s")
    step = output["step"]
    steps = stop / step
    limits.check("steps", steps, f"[output] step = {step!r} s to stop_time = {stop!r} s")
    limits.memory(steps * (1 + len(output["variables"])), f"recording {len(output['variables'])}"
                                                          f" variables every {step!r} s")
    elastic, reason = spec.elastic_choice(values.pop("elastic"), values, train.duration)
    start_values = {k: v for k, v in values.items() if v is not None}
    start_values["elastic"] = elastic
    if elastic:
        _bound_elastic(start_values, stop, limits)
    return Scene(name, start_values, Load.from_train(train, stop), stop, step,
                 list(output["variables"]), reason)


def _bound_elastic(start_values: dict, stop: float, limits: Limits) -> None:
    """Refuse an elastic run whose cells x internal steps pass the work limit."""
    from pipeplug.params import ParameterError, Params
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
