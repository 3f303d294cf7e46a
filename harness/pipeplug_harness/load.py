"""The one load history of the harness: a piecewise-constant struck-end force Q(t).

A :class:`Load` is its change times ``times`` [s] (strictly increasing) and the force
``forces[i]`` [N] that acts from ``times[i]`` to ``times[i + 1]`` (the last one for ever); before
``times[0]`` the force is 0. It is right-continuous: at a change time it takes the value after
the change, which is the force of a communication step that starts there. Every form of load the
harness meets is built into one:

* a blow train (:meth:`Load.from_train`, the Hammer FMU's rules: :mod:`pipeplug_fmu.blows`);
* pulses ``(start, duration, amplitude)`` (:meth:`Load.from_pulses`), summed where they overlap;
* segments ``(duration, Q)`` one after another from t = 0 (:meth:`Load.from_segments`), their
  change times summed in order, as the independent reference sums them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Load", "NO_LOAD"]


@dataclass(frozen=True)
class Load:
    """A piecewise-constant force (see the module docstring)."""

    times: tuple = ()        #: change times [s], strictly increasing
    forces: tuple = ()       #: the force from each change time on [N]

    def __post_init__(self):
        if len(self.times) != len(self.forces):
            raise ValueError("a load needs one force per change time")
        if any(not b > a for a, b in zip(self.times, self.times[1:])):
            raise ValueError("the change times of a load must increase strictly")

    # Construction ------------------------------------------------------------------------------
    @classmethod
    def from_pulses(cls, pulses) -> Load:
        """The sum of rectangular pulses ``(start [s], duration [s], amplitude [N])``."""
        pulses = [(float(s), float(d), float(a)) for s, d, a in pulses if d > 0.0 and a != 0.0]
        if not pulses:
            return NO_LOAD
        starts = np.array([s for s, _, _ in pulses])
        ends = starts + np.array([d for _, d, _ in pulses])
        amplitudes = np.array([a for _, _, a in pulses])
        times, index = np.unique(np.concatenate([starts, ends]), return_inverse=True)
        steps = np.zeros(times.size)
        np.add.at(steps, index, np.concatenate([amplitudes, -amplitudes]))
        forces = np.cumsum(steps)
        forces[np.isclose(forces, 0.0, rtol=0.0, atol=1e-12 * np.abs(amplitudes).max())] = 0.0
        return cls(tuple(times.tolist()), tuple(forces.tolist()))

    @classmethod
    def from_train(cls, train, stop: float = math.inf) -> Load:
        """A blow train (:class:`pipeplug_fmu.blows.BlowTrain`) up to ``stop`` [s] (a train
        without end needs a finite ``stop``)."""
        count = train.count or max(0, math.ceil((stop - train.start) / train.period))
        k = np.arange(count, dtype=float)
        starts = train.start + k * train.period
        starts = starts[starts < stop]
        return cls.from_pulses((s, train.duration, train.amplitude) for s in starts)

    @classmethod
    def from_segments(cls, segments) -> Load:
        """Segments ``(duration [s], Q [N])`` one after another from t = 0, then Q = 0."""
        times, t = [0.0], 0.0
        for duration, _ in segments:
            t += duration
            times.append(t)
        return cls(tuple(times), tuple(float(q) for _, q in segments) + (0.0,))

    # Evaluation --------------------------------------------------------------------------------
    def at(self, t):
        """The force [N] at times ``t`` [s] (right-continuous): a number for a number."""
        if not self.times:
            return 0.0 if np.ndim(t) == 0 else np.zeros(np.shape(t))
        k = np.searchsorted(np.asarray(self.times), np.asarray(t, dtype=float), side="right") - 1
        values = np.where(k >= 0, np.asarray(self.forces)[np.clip(k, 0, None)], 0.0)
        return float(values) if np.ndim(t) == 0 else values

    def on_steps(self, starts) -> np.ndarray:
        """The force [N] held over communication steps that start at ``starts`` [s]."""
        return np.asarray(self.at(np.asarray(starts, dtype=float)), dtype=float)

    def changes_within(self, start: float, stop: float) -> list[float]:
        """The change times strictly between ``start`` and ``stop`` [s]."""
        return [t for t in self.times if start < t < stop]

    def end(self) -> float:
        """The last change time [s] (0 for no load)."""
        return self.times[-1] if self.times else 0.0

    def signal(self, stop: float, strikes=()) -> np.ndarray:
        """The input signal of fmpy's ``simulate_fmu`` from 0 to ``stop`` [s]: each change on
        a duplicated time stamp, so the step starting there sees the new value. PipePlug's
        other inputs are the ram's: ``strikes`` ((time [s], velocity [m/s]) each) raise the
        counter ``strikes`` at their times, with ``v_strike``; without them both hold their
        start values; ``cleanouts`` stays 0 (fmpy warns of every input a signal leaves out)."""
        at = {float(t): v for t, v in strikes}
        points = sorted({0.0, *self.changes_within(0.0, stop), *(t for t in at if t < stop),
                         stop})
        rows, count, speed = [], 0, 0.0
        for a, b in zip(points[:-1], points[1:]):
            if a in at:
                count, speed = count + 1, at[a]
            q = self.at(a)
            rows += [(a, q, count, speed, 0), (b, q, count, speed, 0)]
        return np.array(rows, dtype=[("time", np.float64), ("Q", np.float64),
                                     ("strikes", np.int32), ("v_strike", np.float64),
                                     ("cleanouts", np.int32)])


#: no force at all
NO_LOAD = Load()
