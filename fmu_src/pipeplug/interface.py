"""The one interface of every model variant: its outputs (the one table of them) and methods.

A model is built once by :func:`pipeplug.build_model` from validated parameters and options;
only the effects they call for exist in it. It is then advanced by steps during which the
struck-end force Q is constant::

    model = build_model({"tau1": 2e4}, {"solver": "exact"})
    model.advance(q=23e3, h=1e-3)       # Q in N, h in s
    model.outputs()                     # Outputs(v_pipe=..., ...)
    s = model.get_state(); ...; model.set_state(s)

:data:`OUTPUTS` is the only place where the outputs are declared: the FMU registers its
variables from it, the harness reads its columns by it, and :class:`Outputs` is built from it.
"""
from __future__ import annotations

from typing import NamedTuple, Protocol

import numpy as np

__all__ = ["Output", "OUTPUTS", "OUTPUT_NAMES", "Outputs", "Model", "ModelBase"]


class Output(NamedTuple):
    """One row of the output table."""

    name: str
    unit: str          #: SI unit; "1" for the integer modes
    kind: str          #: "Real" or "Integer"
    meaning: str


#: The outputs, in the order of :class:`Outputs` (the contract's table).
OUTPUTS: tuple[Output, ...] = (
    Output("v_pipe", "m/s", "Real", "pipe velocity (elastic model: at section x_monitor)"),
    Output("v_plug", "m/s", "Real",
           "plug velocity (elastic model: at the plug section coupled to x_monitor)"),
    Output("u_pipe", "m", "Real", "pipe displacement (elastic model: at section x_monitor)"),
    Output("u_plug", "m", "Real",
           "plug displacement (elastic model: at the plug section coupled to x_monitor)"),
    Output("F_outer", "N", "Real", "total friction force of the soil on the pipe, along +x (a "
                                   "stuck contact gives its static reaction)"),
    Output("F_inner", "N", "Real",
           "total friction force of the plug on the pipe, along +x (same rule)"),
    Output("W_input", "J", "Real", "work done by Q since t = 0"),
    Output("W_friction", "J", "Real", "friction work dissipated since t = 0 (never decreases)"),
    Output("pipe_mode", "1", "Integer", "pipe/soil contact: -1 sliding backward, 0 stuck to the "
                                        "soil, 1 sliding forward (elastic: at x_monitor)"),
    Output("plug_mode", "1", "Integer", "pipe/plug contact: sign(v_pipe - v_plug); 0 = stuck "
                                        "together or no plug (elastic: at x_monitor)"),
)

OUTPUT_NAMES: tuple[str, ...] = tuple(o.name for o in OUTPUTS)

Outputs = NamedTuple("Outputs", [(o.name, float if o.kind == "Real" else int) for o in OUTPUTS])
Outputs.__doc__ = "The outputs at the model's current time, SI units (see :data:`OUTPUTS`)."
Outputs.__module__ = __name__


class Model(Protocol):
    """What every model variant offers."""

    time: float  #: the model's own time [s]

    def advance(self, q: float, h: float) -> None:
        """Advance by ``h`` [s] > 0 under a constant struck-end force ``q`` [N]."""

    def outputs(self) -> Outputs:
        """The outputs at the current time (forces under the last step's Q)."""

    def sample(self, q: float, times, names=OUTPUT_NAMES) -> dict:
        """Advance to ``times[-1]`` under a constant ``q`` [N], recording ``names`` at ``times``."""

    def energies(self) -> tuple[float, float, float]:
        """Kinetic energy, elastic energy and the scheme's reversing work [J]."""

    def get_state(self) -> dict:
        """A copy of the whole internal state: plain floats, ints and numpy arrays."""

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (copied, so it can be restored again)."""


class ModelBase:
    """Shared parts of the protocol: dense output by stepping from sample to sample."""

    time: float

    def sample(self, q: float, times, names=OUTPUT_NAMES) -> dict:
        """Advance to each of ``times`` [s] (increasing, later than :attr:`time`) under a
        constant ``q`` [N] and record the outputs ``names`` there.

        Returns
        -------
        dict of arrays
            One array per requested output name.
        """
        times = np.asarray(times, dtype=float)
        rows = [OUTPUT_NAMES.index(name) for name in names]
        table = np.empty((len(rows), len(times)))
        for k, t in enumerate(times):
            self.advance(q, float(t) - self.time)
            out = self.outputs()
            table[:, k] = [out[row] for row in rows]
        return dict(zip(names, table))
