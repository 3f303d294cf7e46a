"""Hammer: the co-simulation slave of a train of rectangular blows or ram strikes (FMI 2.0 and
3.0: :class:`HammerSlave` imports no FMI library; the FMUs' classes put a binding after it).

The train and its parameter table are :mod:`~pipeplug_fmu.blows`; this adapter registers them
on the FMUs' FMI base (:mod:`pipeplug_fmu.base`: call sequence, refusals and FMU state, as for
PipePlug), checks them at ``exitInitializationMode`` and sets its one output from the train at
each communication point.

Output timing: Q (and strikes) at the FMU's current time t is the value for the step that
starts at t, so a host that steps Hammer and PipePlug on a grid containing the blow edges hands
PipePlug the exact train with no one-step delay:

* in initialization mode and right after ``exitInitializationMode``: the values at t_start, the
  start time of ``fmi2SetupExperiment`` (from the parameter values set so far; 0 while they are
  invalid);
* after ``doStep(t, h)``: the values at t + h, for the step on [t + h, next point).

Like PipePlug it keeps its own time and adopts the host's within ``1e-9 max(1, |t|)``.

Runs only inside a built Hammer.fmu (see :mod:`pipeplug_fmu.build`), in a package whose name
carries the build's content digest.
"""
from __future__ import annotations

from .base import FmiBase, Phase, Refuse
from .blows import DEFAULT_EXPERIMENT, DESCRIPTION, OUTPUTS, PARAMETERS, BlowTrainError, check


class HammerSlave(FmiBase):
    author = "PipePlug contributors"
    license = "MIT"
    description = DESCRIPTION
    model_identifier = "Hammer"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.default_experiment = self._experiment(*DEFAULT_EXPERIMENT)

    def _register(self) -> None:
        # Q, the rectangular train's parameters, then the ram's outputs: the value references
        # of the first FMU (Q and the train) stay what they were.
        self._outputs = {}
        self._add_outputs(OUTPUTS[:1])
        for p in PARAMETERS:
            self._add(p.kind, p.name, p.default, p.unit,
                      f"{p.description} [allowed: {p.allowed}]", "parameter", "fixed",
                      bounds=(p.lower, p.upper), allowed=p.allowed)
        self._add_outputs(OUTPUTS[1:])

    def _add_outputs(self, rows) -> None:
        # initial="calculated": they depend on the parameters (InitialUnknowns).
        for name, kind, unit, meaning in rows:
            self._outputs[name] = self._add(kind, name, 0.0 if kind == "Real" else 0, unit,
                                            meaning, "output", "discrete", "calculated")

    # Hooks of the FMI base -----------------------------------------------------------------
    def _build(self, values: dict):
        try:
            return check({p.name: values[p.name] for p in PARAMETERS})
        except BlowTrainError as exc:
            raise Refuse.of(exc.name, exc.value, exc.allowed) from None

    def _step(self, train, t: float, h: float) -> tuple:
        return _values(train, t + h)       # for the step starting at the host's t + h

    def _refresh(self) -> None:
        """The outputs before the first step: the values at the FMU's time (0 while the
        parameters are invalid, which exitInitializationMode refuses)."""
        train = self._model
        if self._phase not in (Phase.STEPPING, Phase.TERMINATED):
            try:
                train = check({p.name: self._tables[p.kind][self._by_name[p.name].vr]
                               for p in PARAMETERS})
            except BlowTrainError:
                train = None
        values = _values(train, self._time) if train is not None else (0.0, 0, 0.0)
        for (name, kind, _, _), value in zip(OUTPUTS, values):
            self._tables[kind][self._outputs[name]] = value

    # modelDescription.xml (build time only) ----------------------------------------------
    def to_xml(self, model_options=None):
        import pipeplug  # the build's core: the project's version (not shipped)

        root = super().to_xml(model_options)
        root.set("version", pipeplug.__version__)
        return root


def _values(train, t: float) -> tuple:
    """The outputs (Q, strikes, v_strike) of ``train`` for the step starting at ``t`` [s]."""
    return train.force(t), train.strikes(t), train.v_strike
