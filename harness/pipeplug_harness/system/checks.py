"""What a system file must pass before libcosim runs it.

libcosim terminates the process when an FMU fails ``exitInitializationMode`` and segfaults on an
SSP file without a step size, and it only warns about a parameter name the FMU does not have. So
every PipePlug and Hammer component's values are checked here with the FMUs' own checks
(:mod:`pipeplug_harness.cosim`), unknown names included, and the times are checked.
"""
from __future__ import annotations

import math

from pipeplug import ParameterError
from pipeplug_fmu import blows, systems
from pipeplug_harness.cosim import check_hammer_parameters, check_parameters

from .files import SystemFile, SystemFileError

__all__ = ["Plan", "check_system", "CHECKS"]

#: modelName -> the check of its parameter values (the FMU's own, see pipeplug_harness.cosim).
CHECKS = {"PipePlug": check_parameters, "Hammer": check_hammer_parameters}
_GRID_TOLERANCE = 1e-9           # of a step: a stop time on the grid


class Plan:
    """A checked system: start, step, number of steps, and warnings for the user."""

    def __init__(self, start: float, step: float, steps: int, warnings: list):
        self.start, self.step, self.steps, self.warnings = start, step, steps, warnings

    @property
    def stop(self) -> float:
        return self.start + self.steps * self.step


def check_system(system: SystemFile, stop: float | None = None, limits=None) -> Plan:
    """Check ``system``; ``stop`` [s] overrides the file's stop time; ``limits``
    (:class:`pipeplug_harness.limits.Limits`) bounds its steps.

    Without either, a system with one Hammer of a finite train stops one period after its last
    blow starts. Raises :class:`SystemFileError` naming the component and the refused value
    (the command adds the file).
    """
    warnings = []
    for component in system.components.values():
        check = CHECKS.get(component.model)
        if check is None:
            warnings.append(f"component {component.name} ({component.model}): its parameters "
                            f"are not checked")
            continue
        try:
            check(component.values)
        except ParameterError as exc:
            raise SystemFileError(f"component {component.name} ({component.model}): {exc}") \
                from None
    if system.step is None:
        raise SystemFileError("no step size (the DefaultExperiment's "
                              "osp:FixedStepAlgorithm baseStepSize): libcosim cannot run it")
    if not (math.isfinite(system.step) and system.step > 0 and math.isfinite(system.start)):
        raise SystemFileError(f"step {system.step!r} s and start "
                              f"{system.start!r} s must be finite, the step > 0")
    stop = _stop(system, stop)
    if not math.isfinite(stop):                # --stop is checked by the command: the file's
        raise SystemFileError(key="DefaultExperiment stopTime", value=stop,
                              allowed="a finite time [s]")
    exact = (stop - system.start) / system.step
    if limits is not None:
        limits.check("steps", exact, f"stop time {stop!r} s in steps of {system.step!r} s")
        limits.memory(exact * (1 + 40), f"{exact:.3g} steps of every input and output")
    steps = math.ceil(exact - _GRID_TOLERANCE)
    if steps < 1:
        raise SystemFileError(f"stop time {stop!r} s: must be after the start "
                              f"{system.start!r} s by at least one step")
    if abs(exact - round(exact)) > _GRID_TOLERANCE:
        warnings.append(f"stop time {stop!r} s is not on the step grid: running {steps} steps")
    for hammer in system.of_model("Hammer"):
        if limits is not None:
            train = blows.check(hammer.values)
            many = (stop - train.start) / train.period + 1
            limits.check("blows", min(many, train.count or many),
                         f"component {hammer.name}: blows every {train.period!r} s to "
                         f"{stop!r} s")
        misses = systems.grid_misses(systems.System(
            hammer=hammer.values, start=system.start, stop=stop, step=system.step))
        if misses:
            shown = ", ".join(f"{edge:.12g}" for edge in misses[:5])
            warnings.append(f"component {hammer.name}: the step {system.step!r} s misses the "
                            f"blow edges [{shown}{', ...' if len(misses) > 5 else ''}] s (each "
                            f"acts at the next grid point)")
    return Plan(system.start, system.step, steps, warnings)


def _stop(system: SystemFile, stop: float | None) -> float:
    if stop is not None:
        return float(stop)
    if system.stop is not None:
        return system.stop
    hammers = system.of_model("Hammer")
    if len(hammers) == 1:
        train = blows.check(hammers[0].values)
        if train.count:
            return train.start + train.count * train.period
    raise SystemFileError("the file gives no stop time: give one with --stop")
