"""PipePlug: the FMI 2.0 co-simulation slave around the :mod:`pipeplug` core (pythonfmu).

A thin adapter: it registers the contract's variables (names, units, defaults and ranges all
read from the core's tables :data:`~pipeplug.OUTPUTS`, :data:`~pipeplug.PARAMETERS` and
:data:`~pipeplug.OPTIONS`), builds the model once at ``exitInitializationMode`` with
:func:`pipeplug.build_model`, advances it in ``doStep`` and copies its outputs. Every refusal is
one log line naming the variable, its value and the allowed range. pythonfmu reports an
exception raised here as fmi2Fatal and ``do_step`` returning False as fmi2Discard; it has no
fmi2Error, so:

* invalid parameters or options, a fixed parameter set after initialization, a set or get of
  an unknown value reference, a failure inside the model: the instance's single exception,
  a :class:`~pipeplug_fmu.fmi.PipePlugRefusal`. pythonfmu logs it as one fmi2Fatal line; the
  FMU's linux64 binary (the loader, ``native/loader.c``) gives the host the refusal's own line
  with fmi2Error instead (pythonfmu's win64 binary, shipped unchanged, still says fmi2Fatal).
  Afterwards the instance answers every call quietly until fmi2Reset;
* a non-finite ``Q``, a communication point that is not the FMU's time, a step past the
  stopTime, a step before initialization: one log line, then discard; the instance stays usable.

Values live in one dict per FMI type, keyed by value reference, so getters and setters are
table look-ups. fmi2Reset is done by pythonfmu itself: it instantiates this class anew.

This module runs only inside a built FMU (see :mod:`pipeplug_fmu.build`): there it sits in a
package whose name carries the build's content digest, next to its own copy of the core
(``<package>.pipeplug``). pythonfmu runs every FMU of a process in one interpreter; distinct
names keep two different builds, and a host's own ``pipeplug``, apart. The whole core is
imported when the slave is, so that no instance needs the files of the folder the FMU was
unpacked into (hosts delete it after a run).
"""
from __future__ import annotations

import importlib
import math
import pkgutil

from pythonfmu import (
    Boolean,
    DefaultExperiment,
    Fmi2Causality,
    Fmi2Initial,
    Fmi2Slave,
    Fmi2Variability,
    Integer,
    Real,
    String,
)
from pythonfmu.enums import Fmi2Status

from . import pipeplug as core
from .fmi import (
    DEFAULT_EXPERIMENT,
    DESCRIPTION,
    INPUT,
    PipePlugRefusal,
    decorate_model_description,
    escape_percent,
    outlive_the_exception,
    refusal,
)

for _module in pkgutil.walk_packages(core.__path__, core.__name__ + "."):
    importlib.import_module(_module.name)        # every model kind, now (see the docstring)

OPTIONS, PARAMETERS, ParameterError = core.OPTIONS, core.PARAMETERS, core.ParameterError

_Q_VR = 0                                         # value reference of Q (registered first)
_OUTPUT_VRS = tuple(range(1, 1 + len(core.OUTPUTS)))   # the outputs follow, in table order
_TIME_TOLERANCE = 1e-9                            # relative, contract "Stepping"
_VR_RANGE = 2 ** 32     # pythonfmu passes fmi2ValueReference (unsigned) as a C int: shown mod this


class PipePlug(Fmi2Slave):
    author = "PipePlug contributors"
    license = "MIT"
    version = core.__version__
    description = DESCRIPTION

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.default_experiment = DefaultExperiment(*DEFAULT_EXPERIMENT)
        self._real, self._int, self._bool, self._str = {}, {}, {}, {}
        self._meta = {}           # value reference -> (name, unit or None, Parameter or None)
        self._params = {}         # parameter/option name -> value reference
        self._model = None        # built at exitInitializationMode
        self._time = 0.0          # the FMU's own time [s]
        self._stop_limit = math.inf
        self._dead = False        # True after the instance's one exception
        self._register_all()

    # Registration -------------------------------------------------------------------------
    def _register_all(self) -> None:
        name, unit, meaning = INPUT
        self._add(Real, self._real, name, 0.0, unit, meaning, causality=Fmi2Causality.input,
                  variability=Fmi2Variability.continuous)
        for out in core.OUTPUTS:
            if out.kind == "Real":
                self._add(Real, self._real, out.name, 0.0, out.unit, out.meaning, **_OUTPUT)
            else:
                kind, table, start = ((Integer, self._int, 0) if out.kind == "Integer"
                                      else (Boolean, self._bool, False))
                self._add(kind, table, out.name, start, None, out.meaning, **dict(
                    _OUTPUT, variability=Fmi2Variability.discrete))
        self._out_tables = tuple(self._table_of(vr) for vr in _OUTPUT_VRS)
        for p in PARAMETERS:
            self._add(Real, self._real, p.name, float(p.default), p.unit,
                      f"{p.description} [allowed: {p.allowed()}]", p, **_PARAMETER)
        for name, (allowed, default, meaning) in OPTIONS.items():
            kind, table = (Boolean, self._bool) if isinstance(default, bool) else (String,
                                                                                   self._str)
            self._add(kind, table, name, default, None,
                      f"{meaning} [allowed: {', '.join(map(repr, allowed))}]", **_PARAMETER)

    def _add(self, kind, table, name, start, unit, meaning, parameter=None, **attributes):
        """Register one variable whose value lives in ``table`` under its value reference."""
        vr = len(self.vars)
        table[vr] = start
        self._meta[vr] = (name, unit, parameter)
        if attributes["causality"] == Fmi2Causality.parameter:
            self._params[name] = vr
        self.register_variable(kind(name, description=meaning, getter=lambda: table[vr],
                                    **attributes))

    # FMI calls ------------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if self._dead:
            return
        self._time = float(start_time)
        self._stop_limit = math.inf if stop_time is None else (
            stop_time + _TIME_TOLERANCE * max(1.0, abs(stop_time)))

    def exit_initialization_mode(self):
        if self._dead or self._model is not None:
            return
        params = {p.name: self._real[self._params[p.name]] for p in PARAMETERS}
        options = {name: self._value(self._params[name]) for name in OPTIONS}
        try:
            # The exact rigid solver runs as plain Python here: a whole run is faster without
            # numba's import (README, "Performance of the FMU"); elastic kernels compile.
            self._model = core.build_model(params, options, compiled=False)
        except ParameterError as exc:
            self._refuse(refusal(exc.name, exc.value, exc.allowed))
        except ImportError as exc:
            name = "elastic" if options["elastic"] else "solver"
            self._refuse(refusal(name, options[name], f"a model available in this build "
                                                     f"(it cannot be loaded: {exc})"))
        except Exception as exc:
            self._refuse(f"the model cannot be built: {type(exc).__name__}: {exc}")

    def do_step(self, current_time, step_size):
        model, t, q = self._model, self._time, self._real[_Q_VR]
        # Written so that NaN fails every test: ``not (x <= bound)`` rather than ``x > bound``.
        if (model is None or not abs(current_time - t) <= _TIME_TOLERANCE * max(1.0, abs(t))
                or not step_size > 0.0 or not current_time + step_size <= self._stop_limit
                or not current_time + step_size > t or not q - q == 0.0):
            return self._refuse_step(current_time, step_size)
        try:
            # From the host's point to the host's next point: hosts computing t = k h and
            # t += h both get outputs at exactly their own points, and a Q they switch acts
            # at their instant (the model keeps no clock of its own).
            model.advance_to(q, current_time + step_size, current_time)
            out = model.outputs()
        except Exception as exc:
            self._refuse(f"the model failed at t = {t!r} s: {type(exc).__name__}: {exc}")
            return False
        self._time = current_time + step_size
        for table, vr, value in zip(self._out_tables, _OUTPUT_VRS, out):
            table[vr] = value
        return True

    def _refuse_step(self, current_time, step_size) -> bool:
        """Log why a doStep is refused (quietly once dead) and return False (discard)."""
        if self._dead:
            return False
        t, q = self._time, self._real[_Q_VR]
        if self._model is None:
            line = "doStep is not allowed before exitInitializationMode"
        elif not math.isfinite(q):
            line = refusal("Q", q, "finite [N]")
        elif not abs(current_time - t) <= _TIME_TOLERANCE * max(1.0, abs(t)):
            line = refusal("currentCommunicationPoint", current_time,
                           f"the FMU time {t!r} s within 1e-9*max(1, |t|)")
        elif not step_size > 0.0:
            line = refusal("communicationStepSize", step_size, "> 0 s")
        elif not current_time + step_size > t:
            line = refusal("currentCommunicationPoint + communicationStepSize",
                           current_time + step_size, f"> the FMU time {t!r} s")
        else:
            line = refusal("currentCommunicationPoint + communicationStepSize",
                           current_time + step_size, f"<= stopTime (+1e-9*max(1, |stopTime|)), "
                                                     f"here <= {self._stop_limit!r} s")
        self._log(line, Fmi2Status.discard)
        return False

    # Getters and setters: table look-ups, refusals for anything else -----------------------
    def get_real(self, vrs):
        return self._get(self._real, vrs, "Real")

    def get_integer(self, vrs):
        return self._get(self._int, vrs, "Integer")

    def get_boolean(self, vrs):
        return self._get(self._bool, vrs, "Boolean")

    def get_string(self, vrs):
        return self._get(self._str, vrs, "String")

    def _get(self, table, vrs, kind):
        try:
            return list(map(table.__getitem__, vrs))
        except KeyError:
            bad = next(vr for vr in vrs if vr not in table)
            self._refuse(refusal("valueReference", bad % _VR_RANGE,
                                f"a {kind} variable of PipePlug"))
            return [table.get(vr, _EMPTY[kind]) for vr in vrs]

    def set_real(self, vrs, values):
        if len(vrs) == 1 and vrs[0] == _Q_VR:        # the input, every step: no checks here
            self._real[_Q_VR] = values[0]
            return
        self._set(self._real, vrs, values, "Real")

    def set_integer(self, vrs, values):
        self._set(self._int, vrs, values, "Integer")

    def set_boolean(self, vrs, values):
        self._set(self._bool, vrs, values, "Boolean")

    def set_string(self, vrs, values):
        self._set(self._str, vrs, values, "String")

    def _set(self, table, vrs, values, kind):
        for vr, value in zip(vrs, values):
            if self._dead:
                return
            name = self._meta.get(vr, ("valueReference",))[0]
            if vr not in table or (vr != _Q_VR and name not in self._params):
                self._refuse(refusal(name if vr in table else "valueReference",
                                    value if vr in table else vr % _VR_RANGE,
                                    f"a settable {kind} variable (the input Q or a parameter)"))
            elif vr != _Q_VR and self._model is not None:
                self._refuse(refusal(name, value, f"no change after initialization (fixed "
                                                 f"parameter; it stays {table[vr]!r})"))
            else:
                table[vr] = value

    def _table_of(self, vr) -> dict:
        """The value table holding value reference ``vr``."""
        return next(t for t in (self._real, self._int, self._bool, self._str) if vr in t)

    def _value(self, vr):
        return self._table_of(vr)[vr]

    # Logging and the single exception -------------------------------------------------------
    def _log(self, line: str, status: Fmi2Status) -> None:
        self.log(escape_percent(line), status)

    def _refuse(self, line: str) -> None:
        """Raise the instance's one exception, carrying ``line``; quiet once that is done.

        pythonfmu reports the exception as one fmi2Fatal log line that contains ``line`` (after
        :data:`~pipeplug_fmu.fmi.REFUSAL_MARK`); the loader turns it into ``line`` alone, with
        fmi2Error. The line is deliberately not queued with :meth:`log` as well: pythonfmu
        forwards queued messages while the exception is still pending, which calls the host's
        logger (a Python callback in FMPy) with an error set and corrupts the host process's
        heap where no loader buffers the lines (win64).
        """
        if self._dead:
            return
        self._dead, self._model = True, None
        outlive_the_exception(self)
        raise PipePlugRefusal(escape_percent(line))

    # State ----------------------------------------------------------------------------------
    def _get_fmu_state(self):
        """A copy of the whole state: FMU time, stop limit, every variable, the model's state."""
        if self._dead:
            return {}
        state = {"fmu.time": self._time, "fmu.stop_limit": self._stop_limit,
                 "fmu.initialized": self._model is not None}
        for vr, (name, _, _) in self._meta.items():
            state["var." + name] = self._value(vr)
        if self._model is not None:
            for key, value in self._model.get_state().items():
                state["model." + key] = value.copy() if hasattr(value, "copy") else value
        return state

    def _set_fmu_state(self, state):
        if self._dead:
            return
        try:
            self._restore(state)
        except PipePlugRefusal:
            raise
        except Exception as exc:
            self._refuse(refusal("FMUstate", f"{type(exc).__name__}: {exc}", "a state saved by "
                                "fmi2GetFMUstate or fmi2DeSerializeFMUstate of PipePlug"))

    def _restore(self, state) -> None:
        """Set every variable, the FMU time and the stop limit; rebuild and restore the model."""
        for vr, (name, _, _) in self._meta.items():
            self._table_of(vr)[vr] = state["var." + name]
        self._time, self._stop_limit = state["fmu.time"], state["fmu.stop_limit"]
        self._model = None
        if state["fmu.initialized"]:
            self.exit_initialization_mode()           # the model of the saved parameters
            self._model.set_state({k[6:]: (v.copy() if hasattr(v, "copy") else v)
                                   for k, v in state.items() if k.startswith("model.")})

    @staticmethod
    def _fmu_state_to_bytes(state):
        try:
            return core.state_to_bytes(state)
        except Exception:
            return b""     # serialization is refused when it is loaded

    @staticmethod
    def _fmu_state_from_bytes(data):
        try:
            return core.state_from_bytes(data)
        except Exception:
            return {}

    # modelDescription.xml (build time only) ----------------------------------------------
    def to_xml(self, model_options=None):
        root = super().to_xml(model_options or {})
        decorate_model_description(root, [(name, unit, _bounds(name, parameter))
                                          for name, unit, parameter in self._meta.values()])
        return root


_OUTPUT = dict(causality=Fmi2Causality.output, variability=Fmi2Variability.continuous,
               initial=Fmi2Initial.exact)
_PARAMETER = dict(causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed)
_EMPTY = {"Real": 0.0, "Integer": 0, "Boolean": False, "String": ""}


def _bounds(name, parameter) -> tuple:
    """``(min, max)`` of a variable for modelDescription.xml (None: unbounded)."""
    if parameter is not None:
        return parameter.lower, parameter.upper
    if name in _MODES:
        return -1, 1
    return None, None


_MODES = {o.name for o in core.OUTPUTS if o.kind == "Integer"}
