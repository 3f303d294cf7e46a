"""Hammer: the FMI 2.0 co-simulation slave of a train of rectangular blows (pythonfmu).

The train and its parameter table are :mod:`~pipeplug_fmu.blows`; this adapter registers them
on the FMUs' FMI base (:mod:`pipeplug_fmu.base`: call sequence, refusals and FMU state, as for
PipePlug), checks them at ``exitInitializationMode`` and sets its one output from the train at
each communication point.

Output timing: Q at the FMU's current time t is the force for the step that starts at t, so a
host that steps Hammer and PipePlug on a grid containing the blow edges hands PipePlug the exact
train with no one-step delay:

* in initialization mode and right after ``exitInitializationMode``: Q = force(t_start), the
  start time of ``fmi2SetupExperiment`` (from the parameter values set so far; 0 while they are
  invalid);
* after ``doStep(t, h)``: Q = force(t + h), the force on [t + h, next point).

Like PipePlug it keeps its own time and adopts the host's within ``1e-9 max(1, |t|)``.

Runs only inside a built Hammer.fmu (see :mod:`pipeplug_fmu.build`), in a package whose name
carries the build's content digest.
"""
from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

from pythonfmu import DefaultExperiment, Fmi2Causality, Fmi2Initial, Fmi2Variability

from .base import FmiBase, Phase, Refuse
from .blows import DEFAULT_EXPERIMENT, DESCRIPTION, OUTPUT, PARAMETERS, BlowTrainError, check


class Hammer(FmiBase):
    author = "PipePlug contributors"
    license = "MIT"
    description = DESCRIPTION
    model_identifier = "Hammer"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.default_experiment = DefaultExperiment(*DEFAULT_EXPERIMENT)

    def _register(self) -> None:
        name, unit, meaning = OUTPUT
        # Q is initial="calculated": it depends on the parameters (an InitialUnknown).
        self._q = self._add("Real", name, 0.0, unit, meaning, Fmi2Causality.output,
                            Fmi2Variability.discrete, Fmi2Initial.calculated)
        for p in PARAMETERS:
            self._add(p.kind, p.name, p.default, p.unit,
                      f"{p.description} [allowed: {p.allowed}]", Fmi2Causality.parameter,
                      Fmi2Variability.fixed, bounds=(p.lower, None), allowed=p.allowed)

    # Hooks of the FMI base -----------------------------------------------------------------
    def _build(self, values: dict):
        try:
            return check({p.name: values[p.name] for p in PARAMETERS})
        except BlowTrainError as exc:
            raise Refuse.of(exc.name, exc.value, exc.allowed) from None

    def _step(self, train, t: float, h: float) -> tuple:
        return (train.force(t + h),)       # the force of the step starting at the host's t + h

    def _refresh(self) -> None:
        """Q before the first step: the force at the FMU's time (0 while the values are
        invalid, which exitInitializationMode refuses)."""
        train = self._model
        if self._phase not in (Phase.STEPPING, Phase.TERMINATED):
            try:
                train = check({p.name: self._tables[p.kind][self._by_name[p.name].vr]
                               for p in PARAMETERS})
            except BlowTrainError:
                train = None
        self._reals[self._q] = train.force(self._time) if train is not None else 0.0

    # modelDescription.xml (build time only) ----------------------------------------------
    def to_xml(self, model_options=None):
        import pipeplug  # the build's core: the project's version (not shipped)

        root = super().to_xml(model_options)
        root.set("version", pipeplug.__version__)
        SubElement(root.find("ModelStructure"), "InitialUnknowns").append(
            Element("Unknown", index=str(self._q + 1)))
        return root
