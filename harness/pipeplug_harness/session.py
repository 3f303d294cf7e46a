"""The one way the harness drives PipePlug: through the FMU (fmpy) or through the core.

* :class:`FmuSession`: one instance of the FMU through fmpy's raw co-simulation API (FMI 2.0 or
  3.0, as the FMU is), set up once (start values in initialization mode) and stepped by the
  caller, so its state carries over from step to step exactly as the FMU keeps it;
  :meth:`FmuSession.restart` resets it for another run (one instance serves many runs, as in a
  host); with FMI 3.0, :meth:`FmuSession.profiles` reads the profile arrays.
* :class:`CoreSession`: the core model the FMU wraps (:func:`pipeplug.build_model`), stepped as
  the FMU's ``doStep`` steps it, without the FMI layer.
* :func:`run_points`: either session through communication points under a :class:`Load`.
* :func:`fmi_version`: the FMI version of an FMU (2 or 3), checked against the one a command
  asks for.
* :func:`simulate`: fmpy's ``simulate_fmu``, as users call it (a piecewise-constant input with
  each change on a duplicated time stamp); a run that ends early (a refused step, which
  ``simulate_fmu`` reports by ending the result early) is :class:`RunFailed`.

Both sessions give the core's :class:`pipeplug.Outputs` after each step. An FMU file is unpacked
once per process into a temporary folder that is removed when the process ends.
"""
from __future__ import annotations

import atexit
import hashlib
import shutil
import tempfile
from pathlib import Path
from typing import Protocol

import numpy as np

from pipeplug import OUTPUT_NAMES, OUTPUTS, Outputs
from pipeplug_harness.errors import RunFailed, UserError
from pipeplug_harness.load import Load

__all__ = ["Session", "FmuSession", "CoreSession", "run_points", "simulate", "unpacked",
           "split_start_values", "fmi_version", "fmu_inputs"]

_UNPACKED: dict[str, str] = {}          # FMU content digest -> its folder in this process
_TEMP: list[str] = []                   # temporary folders of this process, removed at exit


def _remove_temporary() -> None:
    for folder in _TEMP:
        shutil.rmtree(folder, ignore_errors=True)
    _TEMP.clear()


atexit.register(_remove_temporary)


def unpacked(fmu) -> str:
    """The FMU ``fmu`` (a file, or a folder already unpacked) unpacked once per process.

    Raises
    ------
    UserError
        When ``fmu`` is missing or no FMU.
    """
    path = Path(fmu)
    if path.is_dir():
        if not (path / "modelDescription.xml").is_file():
            raise UserError("a folder without modelDescription.xml: not an unpacked FMU",
                            file=path)
        return str(path.resolve())
    if not path.is_file():
        raise UserError("no such FMU file" if not path.exists() else "is not a regular file",
                        file=path)
    try:
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError as exc:
        raise UserError(f"cannot be read: {exc.strerror or exc}", file=path) from None
    if digest not in _UNPACKED:
        from fmpy import extract
        folder = tempfile.mkdtemp(prefix="pipeplug-fmu-")
        _TEMP.append(folder)
        try:
            _UNPACKED[digest] = extract(str(path), unzipdir=folder)
        except Exception as exc:             # a zip error of any kind: not an FMU
            raise UserError(f"not an FMU (zip): {exc}", file=path) from None
    return _UNPACKED[digest]


def fmi_version(fmu, expected: int | None = None) -> int:
    """The FMI version (2 or 3) of the FMU ``fmu``.

    Raises
    ------
    UserError
        When it is neither, or not ``expected`` (the ``--fmi`` a command was given).
    """
    from fmpy import read_model_description
    given = read_model_description(unpacked(fmu), validate=False).fmiVersion
    version = {"2.0": 2, "3.0": 3}.get(given)
    if version is None or (expected is not None and version != expected):
        allowed = f"an FMI {expected}.0 FMU (--fmi {expected})" if expected else "FMI 2.0, 3.0"
        raise UserError(key="fmiVersion", value=given, allowed=allowed, file=Path(fmu))
    return version


def fmu_inputs(fmu) -> frozenset:
    """The names of the inputs of the FMU ``fmu`` (from its model description)."""
    from fmpy import read_model_description
    md = read_model_description(unpacked(fmu), validate=False)
    return frozenset(v.name for v in md.modelVariables if v.causality == "input")


def split_start_values(start_values: dict) -> tuple[dict, dict]:
    """(parameters, options) of FMU start values by contract name."""
    from pipeplug.options import OPTIONS
    options = {k: v for k, v in start_values.items() if k in OPTIONS}
    return {k: v for k, v in start_values.items() if k not in OPTIONS}, options


#: fmpy's setter and getter names of the FMI 3.0 types, by the project's (FMI 2.0) kinds.
_FMI3_TYPES = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}


class Session(Protocol):
    """What a run needs of an instance: steps under a held Q, strikes, clean-outs, their
    count, close."""

    steps: int       #: communication steps taken
    inputs: frozenset    #: the names of the inputs the instance takes

    def strike(self, velocity: float) -> None:
        """Start a strike of the ram [m/s] with the next step."""

    def cleanout(self) -> None:
        """Clean the plug out with the next step (the input ``cleanouts`` rises by one)."""

    def step(self, t: float, h: float, q: float) -> Outputs:
        """Hold Q = ``q`` [N] from ``t`` to ``t + h`` [s], then read the outputs."""

    def close(self) -> None:
        """Release the instance."""


class FmuSession:
    """A PipePlug FMU instance started with ``start_values`` at t = 0.

    Parameters
    ----------
    fmu : path
        The FMU file or an unpacked FMU folder.
    start_values : dict
        Parameters and options by contract name.
    name : str
        The instance name.
    """

    def __init__(self, fmu, start_values: dict | None = None, name: str = "pipeplug"):
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave
        from fmpy.fmi3 import FMU3Slave

        folder = unpacked(fmu)
        md = read_model_description(folder)
        self.fmi = fmi_version(folder)
        self._vars = {v.name: v for v in md.modelVariables}
        self.inputs = frozenset(v.name for v in md.modelVariables if v.causality == "input")
        slave = FMU3Slave if self.fmi == 3 else FMU2Slave
        self._fmu = slave(guid=md.guid, unzipDirectory=folder,
                          modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self._fmu.instantiate(loggingOn=False)
        types = _FMI3_TYPES if self.fmi == 3 else {kind: kind for kind in _FMI3_TYPES}
        self._q = [self._vars["Q"].valueReference]
        self._set_q = getattr(self._fmu, "set" + types["Real"])
        self._read = [([self._vars[o.name].valueReference for o in OUTPUTS if o.kind == kind],
                       [i for i, o in enumerate(OUTPUTS) if o.kind == kind],
                       getattr(self._fmu, "get" + types[kind]))
                      for kind in ("Real", "Integer", "Boolean")]
        self._fresh = True
        self.steps = 0
        if start_values is not None:
            self.restart(start_values)

    def restart(self, start_values: dict) -> None:
        """Reset the instance (unless new) and initialize it with ``start_values`` at t = 0."""
        if not self._fresh:
            self._fmu.reset()
        self._fresh = False
        if self.fmi == 3:
            for name, value in start_values.items():   # structural parameters first
                self._set(name, value)
            self._fmu.enterInitializationMode(startTime=0.0)
        else:
            self._fmu.setupExperiment(startTime=0.0)
            self._fmu.enterInitializationMode()
            for name, value in start_values.items():
                self._set(name, value)
        self._fmu.exitInitializationMode()
        self.steps = 0
        self._strikes = self._cleanouts = 0

    def _set(self, name: str, value) -> None:
        """Set one variable with the setter of its FMI type."""
        v = self._vars[name]
        cast = {"Real": float, "Float64": float, "Integer": int, "Int32": int, "UInt64": int,
                "Boolean": bool, "String": str}[v.type]
        getattr(self._fmu, "set" + v.type)([v.valueReference], [cast(value)])

    def strike(self, velocity: float) -> None:
        """Start a strike of the ram [m/s] with the next step: the input ``strikes`` rises
        by one, ``v_strike`` is ``velocity``."""
        self._strikes += 1
        self._set("v_strike", velocity)
        self._set("strikes", self._strikes)

    def cleanout(self) -> None:
        """Clean the plug out with the next step: the input ``cleanouts`` rises by one (an FMU
        without it has refused the drive before, :func:`pipeplug_harness.drive.run.
        check_inputs`)."""
        self._cleanouts += 1
        self._set("cleanouts", self._cleanouts)

    def step(self, t: float, h: float, q: float) -> Outputs:
        """Hold Q = ``q`` [N] over the communication step from ``t`` to ``t + h`` [s], then
        read every output."""
        self._set_q(self._q, [q])
        self._fmu.doStep(t, h)
        self.steps += 1
        values = [None] * len(OUTPUTS)
        for refs, where, getter in self._read:
            for i, value in zip(where, getter(refs)):
                values[i] = value
        return Outputs(*values)

    def profiles(self, names=None) -> dict:
        """The profile arrays (FMI 3.0; default all of :data:`pipeplug.PROFILES`) by name,
        ``profile_points`` values each."""
        from pipeplug.interface import PROFILES
        if self.fmi != 3:
            raise UserError(key="profiles", value="FMI 2.0",
                            allowed="an FMI 3.0 FMU (profile arrays are FMI 3.0 only)")
        n = self._fmu.getUInt64([self._vars["profile_points"].valueReference])[0]
        return {name: np.array(self._fmu.getFloat64([self._vars[name].valueReference],
                                                    nValues=n))
                for name in names or [p.name for p in PROFILES]}

    def close(self) -> None:
        self._fmu.terminate()
        self._fmu.freeInstance()

    def __enter__(self) -> FmuSession:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class CoreSession:
    """A core model started with ``start_values`` at t = 0 (``builder``: a function with the
    signature of :func:`pipeplug.build_model`, default that one).

    Raises
    ------
    pipeplug.ParameterError
        Naming the offending parameter or option (the FMU refuses the same values).
    """

    def __init__(self, start_values: dict, builder=None):
        from pipeplug import build_model
        params, options = split_start_values(start_values)
        self.model = (builder or build_model)(params, options)
        self.steps = 0
        # the FMU's inputs the model's methods stand for (a model that cleans out has one)
        self.inputs = frozenset({"Q", "strikes", "v_strike"}
                                | ({"cleanouts"} if hasattr(self.model, "clean_out") else set()))

    def strike(self, velocity: float) -> None:
        """Start a strike of the ram [m/s] with the next step (as the FMU's input
        ``strikes`` rising)."""
        self.model.strike(velocity)

    def cleanout(self) -> None:
        """Clean the plug out with the next step (as the FMU's input ``cleanouts`` rising)."""
        self.model.clean_out()

    def step(self, t: float, h: float, q: float) -> Outputs:
        """Hold Q = ``q`` [N] from ``t`` to ``t + h`` [s] (as the FMU's doStep: from the host's
        ``t`` to exactly ``t + h``), then read the outputs."""
        self.model.advance_to(q, t + h, t)
        self.steps += 1
        return self.model.outputs()

    def close(self) -> None:
        self.model = None

    def __enter__(self) -> CoreSession:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def run_points(session: Session, load: Load, points) -> np.ndarray:
    """Step ``session`` from each of ``points`` [s] to the next under the load there.

    Returns
    -------
    ndarray, shape (len(points) - 1, outputs)
        The outputs after each step, in the order of :data:`pipeplug.OUTPUT_NAMES`.
    """
    points = np.asarray(points, dtype=float)
    loads = load.on_steps(points[:-1])
    rows = np.empty((len(points) - 1, len(OUTPUT_NAMES)))
    for i in range(len(points) - 1):
        rows[i] = session.step(float(points[i]), float(points[i + 1] - points[i]),
                               float(loads[i]))
    return rows


def simulate(fmu, start_values: dict, load: Load, step: float, stop: float,
             outputs=OUTPUT_NAMES, strikes=()) -> np.ndarray:
    """fmpy's ``simulate_fmu`` from 0 to ``stop`` [s] every ``step`` [s] under ``load`` and the
    ram's ``strikes`` ((time [s], velocity [m/s]) each), with every load change and strike a
    communication point; checked to reach ``stop``.

    Returns
    -------
    numpy structured array
        ``time`` and the requested outputs, one row per communication point.

    Raises
    ------
    RunFailed
        When the FMU refused a step (the result ends before ``stop``).
    """
    from fmpy import simulate_fmu
    result = simulate_fmu(
        unpacked(fmu), fmi_type="CoSimulation", start_time=0.0, stop_time=stop,
        output_interval=step, start_values=dict(start_values), input=load.signal(stop, strikes),
        output=list(outputs), validate=False)
    last = float(result["time"][-1])
    if abs(last - stop) > 1e-9 * max(1.0, stop):
        raise RunFailed(f"the FMU stopped at t = {last:.9g} s before the stop time {stop:.9g} s "
                        f"(it refused a step)")
    return result
