"""One PipePlug instance for a whole drive: the FMU's (:class:`FmuSession`) or the core's
(:class:`CoreSession`), both of the small interface :class:`Session` the drive loop uses.

:class:`FmuSession` drives the FMU through FMPy's raw FMI 2.0 co-simulation API: the instance is
set up once (start values in initialization mode, no stop time) and stepped by the caller; its
state therefore carries over from blow to blow exactly as the FMU keeps it. A refused step
raises (FMPy turns a discard or fatal status into an exception).

:class:`CoreSession` steps the core model the FMU wraps (:func:`pipeplug.build_model`) as the
FMU's ``doStep`` does, from the host's point to the host's next point, without the FMI layer:
many drives in one process (sweeps) at the core's speed.
"""
from __future__ import annotations

import os
from typing import NamedTuple, Protocol

__all__ = ["Reading", "Session", "FmuSession", "CoreSession"]

_REALS = ("v_pipe", "v_plug", "u_pipe", "W_input", "W_friction_outer", "W_friction_inner",
          "E_kinetic", "E_strain", "W_numerical", "W_ram", "W_cushion")


class Reading(NamedTuple):
    """The outputs a drive reads after each communication step (SI)."""

    v_pipe: float
    v_plug: float
    u_pipe: float
    W_input: float
    W_friction_outer: float
    W_friction_inner: float
    E_kinetic: float
    E_strain: float
    W_numerical: float
    W_ram: float
    W_cushion: float
    at_rest: bool

    @property
    def W_friction(self) -> float:
        """Friction work [J], both contacts."""
        return self.W_friction_outer + self.W_friction_inner


class Session(Protocol):
    """What the drive loop needs of an instance: steps under a held Q, their count, close."""

    steps: int       #: communication steps taken

    def step(self, t: float, h: float, q: float) -> Reading:
        """Hold Q = ``q`` [N] from ``t`` to ``t + h`` [s], then read the outputs."""

    def close(self) -> None:
        """Release the instance."""


class FmuSession:
    """A PipePlug instance started with ``start_values`` at t = 0.

    Parameters
    ----------
    fmu : path
        The FMU file.
    start_values : dict
        Parameters and options by contract name.
    """

    def __init__(self, fmu: str | os.PathLike, start_values: dict):
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave

        from pipeplug_harness.fmu_run import extracted

        unzipped = extracted(fmu)
        md = read_model_description(unzipped)
        self._vars = {v.name: v for v in md.modelVariables}
        self._fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                              modelIdentifier=md.coSimulation.modelIdentifier,
                              instanceName="drive")
        self._fmu.instantiate()
        self._fmu.setupExperiment(startTime=0.0)
        self._fmu.enterInitializationMode()
        for name, value in start_values.items():
            self._set(name, value)
        self._fmu.exitInitializationMode()
        self._q = self._vars["Q"].valueReference
        self._reals = [self._vars[n].valueReference for n in _REALS]
        self._rest = [self._vars["at_rest"].valueReference]
        self.steps = 0       #: communication steps taken

    def _set(self, name: str, value) -> None:
        """Set one variable with the setter of its FMI type."""
        v = self._vars[name]
        if v.type == "String":
            value = str(value).encode()
        getattr(self._fmu, "set" + v.type)([v.valueReference], [value])

    def step(self, t: float, h: float, q: float) -> Reading:
        """Hold Q = ``q`` [N] over the communication step from ``t`` to ``t + h`` [s], then
        read the outputs."""
        self._fmu.setReal([self._q], [q])
        self._fmu.doStep(t, h)
        self.steps += 1
        return Reading(*self._fmu.getReal(self._reals), bool(self._fmu.getBoolean(self._rest)[0]))

    def close(self) -> None:
        self._fmu.terminate()
        self._fmu.freeInstance()

    def __enter__(self) -> FmuSession:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class CoreSession:
    """A core model (:func:`pipeplug.build_model`) started with ``start_values`` at t = 0.

    Parameters
    ----------
    start_values : dict
        Parameters and options by contract name, as for :class:`FmuSession`.

    Raises
    ------
    pipeplug.ParameterError
        Naming the offending parameter or option (the FMU refuses the same values).
    """

    def __init__(self, start_values: dict):
        from pipeplug import build_model
        from pipeplug.options import OPTIONS
        options = {k: v for k, v in start_values.items() if k in OPTIONS}
        params = {k: v for k, v in start_values.items() if k not in OPTIONS}
        self.model = build_model(params, options)
        self.steps = 0       #: communication steps taken

    def step(self, t: float, h: float, q: float) -> Reading:
        """Hold Q = ``q`` [N] from ``t`` to ``t + h`` [s] (as the FMU's doStep: the step starts
        at the host's ``t`` and ends at exactly ``t + h``), then read the outputs."""
        self.model.advance_to(q, t + h, t)
        self.steps += 1
        o = self.model.outputs()
        return Reading(*(getattr(o, name) for name in _REALS), o.at_rest)

    def close(self) -> None:
        self.model = None

    def __enter__(self) -> CoreSession:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
