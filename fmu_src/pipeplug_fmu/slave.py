"""PipePlug: the co-simulation slave around the :mod:`pipeplug` core, for FMI 2.0 and 3.0.

A thin adapter on the FMUs' FMI base (:mod:`pipeplug_fmu.base`, which holds the call sequence,
the refusals and the FMU state): it registers the contract's variables (names, units, defaults
and ranges all read from the core's tables :data:`~pipeplug.OUTPUTS`,
:data:`~pipeplug.PARAMETERS` and :data:`~pipeplug.OPTIONS`), builds the model with
:func:`pipeplug.build_model` at ``exitInitializationMode``, advances it in ``doStep`` and hands
its outputs and state to the base.

Refusals of its own: a parameter or option the core refuses (fmi2Error, the core's line); a
non-finite ``Q``, or a step the core refuses with :class:`~pipeplug.ParameterError` (too many
internal steps, say), is fmi2Discard with that line and changes nothing; a step whose values
overflow (an ArithmeticError of the core: a huge force or step) is fmi2Error naming ``Q``, the
step and the overflow.

:class:`PipePlugSlave` imports no FMI library: the FMUs' classes put a binding after it
(:mod:`pipeplug_fmu.fmi2`, :mod:`pipeplug_fmu.fmi3`). On a binding with arrays (FMI 3.0) it
also registers the structural parameter ``profile_points`` and the profile arrays of
:data:`pipeplug.interface.PROFILES`, sized by it.

This module runs only inside a built FMU (see :mod:`pipeplug_fmu.build`): there it sits in a
package whose name carries the build's content digest, next to its own copy of the core
(``<package>.pipeplug``). pythonfmu runs every FMU of a process in one interpreter; distinct
names keep two different builds, and a host's own ``pipeplug``, apart. The whole core is
imported when the slave is, so that no instance needs the files of the folder the FMU was
unpacked into (hosts delete it after a run).
"""
from __future__ import annotations

import importlib
import pkgutil
import re
import warnings

from . import pipeplug as core
from .base import Discard, FmiBase, Phase, Refuse, conformity
from .fmi import DEFAULT_EXPERIMENT, DESCRIPTION, INPUTS, refusal

for _module in pkgutil.walk_packages(core.__path__, core.__name__ + "."):
    importlib.import_module(_module.name)        # every model kind, now (see the docstring)

# numpy's warnings from this copy of the core (an overflow in a step refused afterwards by name)
# would be printed on the host's stderr: the refusal's line says it to the host's logger.
warnings.filterwarnings("ignore", category=RuntimeWarning, module=re.escape(core.__name__) + r"\.")

_KIND_OF_OUTPUT = {"Real": ("Real", "continuous", 0.0), "Integer": ("Integer", "discrete", 0),
                   "Boolean": ("Boolean", "discrete", False)}
_MODES = {o.name for o in core.OUTPUTS if o.kind == "Integer"}
_SEEN = "fmu_strikes_seen"     # the adapter's own fields in an FMU state
_CLEANED = "fmu_cleanouts_seen"
_ALLOWED_INPUT = {"Q": "finite [N]", "strikes": "an Integer", "v_strike": "finite [m/s]",
                  "cleanouts": "an Integer"}


class PipePlugSlave(FmiBase):
    author = "PipePlug contributors"
    license = "MIT"
    version = core.__version__
    description = DESCRIPTION
    model_identifier = "PipePlug"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.default_experiment = self._experiment(*DEFAULT_EXPERIMENT)

    def _register(self) -> None:
        # Q, the outputs, the parameters and options, then the ram's inputs: the value
        # references of the FMU before the ram (Q 0, v_pipe 1, ...) stay.
        self._inputs = {}
        self._add_inputs(INPUTS[:1])
        self._q = self._inputs["Q"]
        self._strikes_seen = 0      # the strikes counter the model has acted on
        self._cleanouts_seen = 0    # and the clean-outs counter
        for out in core.OUTPUTS:
            kind, variability, start = _KIND_OF_OUTPUT[out.kind]
            self._add(kind, out.name, start, out.unit, out.meaning, "output", variability,
                      "exact", (-1, 1) if out.name in _MODES else (None, None))
        for p in core.PARAMETERS:
            self._add("Real", p.name, float(p.default), p.unit,
                      f"{p.description} [allowed: {p.allowed()}]", "parameter", "fixed",
                      bounds=(p.lower, p.upper), allowed=p.allowed())
        for name, (allowed, default, meaning) in core.OPTIONS.items():
            shown = ", ".join(map(repr, allowed))
            self._add("Boolean" if isinstance(default, bool) else "String", name, default, None,
                      f"{meaning} [allowed: {shown}]", "parameter", "fixed", allowed=shown)
        self._add_inputs(INPUTS[1:])
        if self.ARRAYS:                         # the binding's: FMI 3.0 has arrays
            self._add_profiles()

    def _add_inputs(self, rows) -> None:
        for name, kind, unit, start, meaning in rows:
            self._inputs[name] = self._add(kind, name, start, unit, meaning, "input",
                                           "continuous" if kind == "Real" else "discrete",
                                           allowed=_ALLOWED_INPUT[name])

    def _add_profiles(self) -> None:
        """profile_points and the profile arrays (after every variable of the FMI 2.0 FMU)."""
        default, lower, upper = core.interface.PROFILE_POINTS
        allowed = f"an integer >= {lower} and <= {upper}"
        self._points = self._add("UInt64", "profile_points", default, None,
                                 f"number of sections of the profile arrays [allowed: "
                                 f"{allowed}]", "structuralParameter", "fixed", "exact",
                                 (lower, upper), allowed)
        self._profile_vrs = tuple(
            self._add("Real", p.name, [0.0] * default, p.unit, p.meaning, "output",
                      "continuous", "exact", size_of=self._points)
            for p in core.interface.PROFILES)

    def _refresh(self) -> None:
        """The profile arrays take the length of profile_points as it is set (zeros); once the
        model is built (fmi2ExitInitializationMode), the outputs are its own at the start (the
        plug's length, at rest), not the registered zeros a host would record at t0."""
        if self._model is not None and self._phase is Phase.STEPPING:
            for (table, vr), value in zip(self._output_slots, self._outputs_of(self._model)):
                table[vr] = value
            return
        if self.ARRAYS:
            n = self._tables["UInt64"][self._points]
            if len(self._reals[self._profile_vrs[0]]) != n and self._model is None:
                _, lower, upper = core.interface.PROFILE_POINTS
                for vr in self._profile_vrs:
                    self._reals[vr] = [0.0] * (n if lower <= n <= upper else 0)

    # Hooks of the FMI base -----------------------------------------------------------------
    def _build(self, values: dict):
        params = {p.name: values[p.name] for p in core.PARAMETERS}
        options = {name: values[name] for name in core.OPTIONS}
        self._strikes_seen = 0      # a counter that rose before the first step strikes then
        self._cleanouts_seen = 0    # (and cleans out then)
        try:
            # The exact rigid solver runs as plain Python here: a whole run is faster without
            # numba's import (README, "Performance of the FMU"); elastic kernels compile.
            return core.build_model(params, options, compiled=False,
                                    profile_points=values.get("profile_points", 0))
        except core.ParameterError as exc:
            raise Refuse.of(exc.name, exc.value, exc.allowed) from None
        except ImportError as exc:
            name = "elastic" if options["elastic"] else "solver"
            raise Refuse.of(name, options[name], f"a model available in this build (it cannot "
                                                 f"be loaded: {exc})") from None

    def _step(self, model, t: float, h: float) -> tuple:
        q = self._reals[self._q]
        if not q - q == 0.0:                                   # NaN or infinite
            raise Discard.of("Q", q, "finite [N]")
        strikes = self._tables["Integer"][self._inputs["strikes"]]
        cleanouts = self._tables["Integer"][self._inputs["cleanouts"]]
        struck = strikes > self._strikes_seen
        cleaned = cleanouts > self._cleanouts_seen
        saved = model.get_state() if struck or cleaned else None
        try:
            if cleaned:
                # One clean-out for any rise, as for strikes.
                model.clean_out()
            if struck:
                # One strike for any rise: strikes at one instant are one strike.
                model.strike(self._reals[self._inputs["v_strike"]])
            # From the host's point to the host's next point: hosts computing t = k h and
            # t += h both get outputs at exactly their own points, and a Q they switch acts at
            # their instant (the model keeps no clock of its own).
            model.advance_to(q, t + h, t)
        except core.ParameterError as exc:          # a step the core cannot take: unchanged
            if saved is not None:
                model.set_state(saved)
            raise Discard(refusal(exc.name, exc.value, exc.allowed)) from None
        except ArithmeticError as exc:             # values beyond float range: in error
            raise Refuse(refusal("Q", q, f"a force whose step from t = {t!r} s by {h!r} s the "
                                         f"model computes in finite numbers (it overflowed: "
                                         f"{exc}); set a saved FMU state or reset")) from None
        self._strikes_seen, self._cleanouts_seen = strikes, cleanouts
        return self._outputs_of(model)

    def _outputs_of(self, model) -> tuple:
        """The outputs in registration order: the contract's, then the profiles (FMI 3.0)."""
        if self.ARRAYS:
            return (*model.outputs(), *(a.tolist() for a in model.profiles()))
        return model.outputs()

    def _save(self, model) -> dict:
        state = {k: (v.copy() if hasattr(v, "copy") else v) for k, v in model.get_state().items()}
        state[_SEEN], state[_CLEANED] = self._strikes_seen, self._cleanouts_seen
        return state

    def _load(self, model, saved: dict) -> None:
        wrong = conformity(dict(model.get_state(), **{_SEEN: 0, _CLEANED: 0}), saved)
        if wrong is not None:
            raise Refuse.of(self.STATE, wrong, "the state of a model of these parameters")
        model.set_state({k: (v.copy() if hasattr(v, "copy") else v) for k, v in saved.items()
                         if k not in (_SEEN, _CLEANED)})
        self._strikes_seen, self._cleanouts_seen = int(saved[_SEEN]), int(saved[_CLEANED])

    @classmethod
    def _model_to_bytes(cls, saved: dict) -> bytes:
        return core.state_to_bytes(saved)                      # bit-exact, no pickle

    @classmethod
    def _model_from_bytes(cls, data: bytes) -> dict:
        return core.state_from_bytes(data)
