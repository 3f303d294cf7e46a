"""The one small interface every model variant offers, and how a variant is chosen.

A model is built once from validated parameters and options; only the effects they call for
exist in it (a plug only with plug coupling, outer friction only with tau1 > 0, rods only
with ``elastic``). It is then advanced by steps during which the struck-end force Q is
constant::

    model = build_model({"tau1": 2e4}, {"solver": "exact"})
    model.advance(q=23e3, h=1e-3)       # Q in N, h in s
    model.outputs()                     # Outputs(v_pipe=..., ...)
    s = model.get_state(); ...; model.set_state(s)
"""
from __future__ import annotations

from typing import Mapping, NamedTuple, Protocol

from .options import Options
from .params import Params

__all__ = ["Outputs", "Model", "build_model", "OUTPUT_NAMES"]


class Outputs(NamedTuple):
    """The contract's outputs at the model's current time (SI units)."""

    v_pipe: float      #: pipe velocity [m/s]
    v_plug: float      #: plug velocity [m/s]
    u_pipe: float      #: pipe displacement [m]
    u_plug: float      #: plug displacement [m]
    F_outer: float     #: friction of the soil on the pipe, along +x [N]
    F_inner: float     #: friction of the plug on the pipe, along +x [N]
    W_input: float     #: work of Q since t = 0 [J]
    W_friction: float  #: friction work dissipated since t = 0 [J]
    pipe_mode: int     #: -1 sliding back, 0 stuck, 1 sliding forward
    plug_mode: int     #: sign(v_pipe - v_plug); 0 stuck together or no plug


OUTPUT_NAMES = Outputs._fields


class Model(Protocol):
    """What every model variant offers."""

    time: float  #: the model's own time [s]

    def advance(self, q: float, h: float) -> None:
        """Advance by ``h`` [s] > 0 under a constant struck-end force ``q`` [N]."""

    def outputs(self) -> Outputs:
        """The outputs at the current time (forces under the last step's Q)."""

    def get_state(self) -> dict:
        """A copy of the whole internal state: plain floats, ints and numpy arrays."""

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (copied, so it can be restored again)."""


def build_model(params: Params | Mapping[str, float] | None = None,
                options: Options | Mapping[str, object] | None = None) -> Model:
    """Validate parameters and options and build the model they call for.

    Parameters
    ----------
    params : Params or mapping, optional
        Parameter values by contract name (SI); missing ones take their defaults.
    options : Options or mapping, optional
        ``solver`` ("exact" | "fd"), ``contact_growth`` (bool), ``elastic`` (bool).

    Returns
    -------
    Model
        A fresh model at t = 0, at rest.

    Raises
    ------
    ParameterError
        Naming the offending parameter or option, its value and the allowed set.
    """
    if not isinstance(options, Options):
        options = Options.from_mapping(options)
    if not isinstance(params, Params):
        params = Params.from_mapping(params or {})
    params.validate(options.active_groups())
    if options.elastic:
        from .elastic import ElasticModel
        return ElasticModel(params, options)
    if options.solver == "fd":
        from .rigid_fd import RigidFd
        return RigidFd(params, options)
    from .rigid_exact import RigidExact
    return RigidExact(params, options)
