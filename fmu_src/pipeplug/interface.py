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

import math
from typing import NamedTuple, Protocol

import numpy as np

from .params import ParameterError

__all__ = ["Output", "OUTPUTS", "OUTPUT_NAMES", "PER_STEP", "Outputs", "Model", "ModelBase",
           "LEDGER_SOURCES", "Profile", "PROFILES", "PROFILE_POINTS", "profile_sections",
           "LEDGER_TERMS", "ledger_residual", "GROWTH_OUTPUTS"]


class Output(NamedTuple):
    """One row of the output table."""

    name: str
    unit: str          #: SI unit; "1" for the modes and the flag
    kind: str          #: "Real", "Integer" or "Boolean"
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
    Output("W_friction_outer", "J", "Real",
           "the part of W_friction dissipated between pipe and soil"),
    Output("W_friction_inner", "J", "Real",
           "the part of W_friction dissipated between pipe and plug"),
    Output("E_kinetic", "J", "Real", "kinetic energy of pipe and plug (elastic: the scheme's "
                                     "discrete kinetic energy, >= 0)"),
    Output("E_strain", "J", "Real", "strain energy of pipe, plug and cushion (rigid: the "
                                    "cushion's recoverable energy, 0 without a ram; elastic: "
                                    "the scheme's discrete strain energy, >= 0)"),
    Output("W_numerical", "J", "Real", "energy the numerical scheme dissipated since t = 0 (>= 0; "
                                       "fd: the impulses' share; exact and elastic: 0): W_input "
                                       "= E_kinetic + E_strain + W_friction + W_numerical"),
    Output("F_head", "N", "Real", "force on the pipe head: Q plus the ram's contact force, "
                                  "positive into the soil"),
    Output("v_ram", "m/s", "Real", "velocity of the ram (0 without a ram)"),
    Output("W_ram", "J", "Real", "energy the strikes brought: the ram's kinetic energy at each "
                                 "strike, less the kinetic energy the ram still had"),
    Output("W_cushion", "J", "Real", "energy lost in the cushion (or the direct contact) "
                                     "between ram and head since t = 0, with any energy the "
                                     "cushion still held when a new strike reset it"),
    Output("E_transferred", "J", "Real", "work of F_head on the pipe head since t = 0 (ENTHRU)"),
    Output("stress_head", "Pa", "Real", "axial stress at the head, compression negative"),
    Output("stress_min", "Pa", "Real", "most compressive axial stress anywhere along the pipe "
                                       "during the last communication step (rigid models: "
                                       "from the rigid body's equilibrium, at the step's end "
                                       "without a ram; with one, exact over the step but for "
                                       "a direct impact's impulse)"),
    Output("stress_max", "Pa", "Real", "most tensile axial stress anywhere along the pipe "
                                       "during the last communication step (same rule)"),
    Output("at_rest", "1", "Boolean", "true when a step under Q = 0 would leave the whole state "
                                      "unchanged, bit for bit"),
    Output("pipe_mode", "1", "Integer", "pipe/soil contact: -1 sliding backward, 0 stuck to the "
                                        "soil, 1 sliding forward (elastic: at x_monitor)"),
    Output("plug_mode", "1", "Integer", "pipe/plug contact: sign(v_pipe - v_plug); 0 = stuck "
                                        "together or no plug (elastic: at x_monitor)"),
    Output("W_face", "J", "Real", "work done against the end resistance of the soil on the "
                                  "pipe's front end and the plug's front face since t = 0 "
                                  "(>= 0, never decreases; 0 with q_face = q_plug_face = 0)"),
    Output("W_damping", "J", "Real", "energy dissipated by the Smith damping of the shaft "
                                     "friction and the end resistances since t = 0 (>= 0, "
                                     "never decreases; 0 with J_shaft = J_face = 0)"),
    Output("L2_now", "m", "Real", "the plug's length now (the parameter L2 unless plug_growth or a "
                                  "clean-out changed it)"),
    Output("W_accretion", "J", "Real", "energy lost as soil at rest joins the plug (rigid models "
                                       "also: soil the plug pushes out of the pipe's front end "
                                       "comes to rest, the plug's impact on the head when it "
                                       "fills the pipe) (>= 0, never decreases; 0 without "
                                       "plug_growth)"),
    Output("W_removed", "J", "Real", "energy of the soil the clean-outs removed since t = 0 "
                                     "(kinetic; model III: the scheme's energy it took, its kinetic and "
                                     "strain energy at least; >= 0, never decreases)"),
)

#: The outputs every model without a growing plug gives as constants: L2_now (the parameter L2),
#: W_accretion and W_removed (0).
GROWTH_OUTPUTS: tuple[str, ...] = ("L2_now", "W_accretion", "W_removed")

OUTPUT_NAMES: tuple[str, ...] = tuple(o.name for o in OUTPUTS)

#: The outputs that describe the last communication step as a whole (extremes over it), so
#: that, unlike every other output, they depend on where the host's points fall.
PER_STEP: tuple[str, ...] = ("stress_min", "stress_max")

#: The energy ledger, one table for every model and every check of it: the work the sources put
#: in equals the sum of the stores and sinks, each of which is >= 0 (the dissipated ones never
#: decrease). Effects added later add their terms here.
LEDGER_SOURCES: tuple[str, ...] = ("W_input", "W_ram")
LEDGER_TERMS: tuple[str, ...] = ("E_kinetic", "E_strain", "W_friction", "W_numerical",
                                 "W_cushion", "W_face", "W_damping", "W_accretion", "W_removed")


def ledger_residual(values) -> float:
    """Sources minus terms of the ledger [J] for ``values`` (outputs by name: an
    :class:`Outputs`, or columns of them)."""
    get = values.__getitem__ if isinstance(values, dict) else (lambda n: getattr(values, n))
    return (sum(get(n) for n in LEDGER_SOURCES) - sum(get(n) for n in LEDGER_TERMS))

#: The profiles along the rods (array outputs of ``profile_points`` elements; the FMI 3.0 FMU's):
#: element k is what the scalar output of the same quantity gives with x_monitor at section k
#: (:func:`profile_sections`), bit for bit; rigid models: uniform motion and the axial stress
#: of the rigid body's equilibrium.
class Profile(NamedTuple):
    """One row of the profile table."""

    name: str
    unit: str
    meaning: str


PROFILES: tuple[Profile, ...] = (
    Profile("v_pipe_profile", "m/s", "pipe velocity at the sections x_k = k L1 / (n - 1)"),
    Profile("u_pipe_profile", "m", "pipe displacement at the sections x_k = k L1 / (n - 1)"),
    Profile("stress_pipe_profile", "Pa", "axial stress of the pipe at the sections x_k = k L1 "
                                         "/ (n - 1), compression negative"),
    Profile("v_plug_profile", "m/s", "plug velocity at the sections L1 - L2 + k L2 / (n - 1) "
                                     "over the plug (0 when no plug is simulated)"),
)

#: The number of sections of the profiles: (default, smallest, largest).
PROFILE_POINTS = (11, 2, 100_000)


def profile_sections(L1: float, L2: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The reference sections [m] of the pipe profiles, x_k = k L1 / (n - 1), and of the plug
    profile, L1 - L2 + k L2 / (n - 1), k = 0 .. n-1 (each the x_monitor that gives element k)."""
    pipe = np.array([k * L1 / (n - 1) for k in range(n)])
    plug = np.array([(L1 - L2) + k * L2 / (n - 1) for k in range(n)])
    return np.minimum(pipe, L1), np.minimum(plug, L1)


_TYPES = {"Real": float, "Integer": int, "Boolean": bool}
Outputs = NamedTuple("Outputs", [(o.name, _TYPES[o.kind]) for o in OUTPUTS])
Outputs.__doc__ = "The outputs at the model's current time, SI units (see :data:`OUTPUTS`)."
Outputs.__module__ = __name__


class Model(Protocol):
    """What every model variant offers."""

    time: float  #: the model's own time [s]

    def advance(self, q: float, h: float) -> None:
        """Advance by ``h`` [s] > 0 under a constant struck-end force ``q`` [N]."""

    def advance_to(self, q: float, t_end: float, t_start: float | None = None) -> None:
        """Advance to the absolute time ``t_end`` [s] > :attr:`time` under a constant ``q``
        [N]; :attr:`time` becomes exactly ``t_end`` (a host's own communication point). The
        step starts at ``t_start`` when given (a host's value of the current time)."""

    def at_rest(self) -> bool:
        """True when a step under Q = 0 would leave the whole state unchanged, bit for bit
        (then such steps cost nothing)."""

    def outputs(self) -> Outputs:
        """The outputs at the current time (forces under the last step's Q)."""

    def sample(self, q, times, names=OUTPUT_NAMES) -> dict:
        """Advance through ``times`` [s] under ``q`` [N] (constant, or ``q[j]`` over the
        interval ending at ``times[j]``), recording ``names`` at ``times``."""

    def modes(self) -> tuple[tuple[int, int], ...]:
        """The contact modes the run went through, in order: ``(pipe_mode, plug_mode)`` as in
        the outputs, consecutive repeats merged (exact: every piece between events; fd: every
        internal step; elastic: at x_monitor after every communication step)."""

    def clean_out(self) -> None:
        """Remove the plug down to ``L2_after_cleanout`` now (``plug_growth``; other models
        raise :class:`~pipeplug.params.ParameterError`)."""

    def get_state(self) -> dict:
        """A copy of the whole internal state: plain floats, ints and numpy arrays."""

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (copied, so it can be restored again)."""


class ModelBase:
    """Shared parts of the protocol: stepping by a length or to a time, dense output.

    A variant implements ``_step_to(q, h, t_end)``: advance by ``h`` under ``q`` and end at
    the time ``t_end`` (``h`` and ``t_end - time`` agree to round-off; the variant takes the
    internal steps from ``h`` and sets :attr:`time` to ``t_end``).
    """

    time: float
    _profiler = None     # set by build_model(profile_points=n): model -> the PROFILES arrays

    def profiles(self) -> tuple[np.ndarray, ...]:
        """The arrays of :data:`PROFILES` at the current time (the model must have been built
        with ``profile_points``)."""
        if self._profiler is None:
            raise ValueError("this model was built without profile_points")
        return self._profiler(self)

    def strike(self, velocity: float) -> None:
        """Start a strike of the ram at ``velocity`` [m/s]; a model with a ram overrides this.

        Raises
        ------
        ParameterError
            Always: this model has no ram (``ram_mass = 0``, or a model that refuses one).
        """
        raise ParameterError("strikes", "an increase", "none without a ram (ram_mass > 0)")

    @staticmethod
    def _check_strike(velocity: float, ram_mass: float) -> None:
        """Refuse a strike at ``velocity`` [m/s] that is not finite or whose ram of
        ``ram_mass`` [kg] would carry a kinetic energy beyond float range (every output after
        it would be inf or nan; the velocity is the input to name)."""
        if not (math.isfinite(velocity) and math.isfinite(0.5 * ram_mass * velocity * velocity)):
            raise ParameterError("v_strike", velocity, "finite [m/s], with a finite kinetic "
                                 "energy of the ram (m v^2 / 2)")

    def clean_out(self) -> None:
        """Remove the plug down to ``L2_after_cleanout`` now; a model with a growing plug
        overrides this.

        Raises
        ------
        ParameterError
            Always: this model's plug does not change (``plug_growth`` is off, or a model that
            does not carry it).
        """
        raise ParameterError("cleanouts", "an increase", "none without plug_growth = True")

    def advance(self, q: float, h: float) -> None:
        """Advance by ``h`` [s] > 0 under a constant struck-end force ``q`` [N]."""
        h = float(h)
        self._check_step(q, h)
        self._step_to(float(q), h, self.time + h)

    def advance_to(self, q: float, t_end: float, t_start: float | None = None) -> None:
        """Advance to the absolute time ``t_end`` [s] under a constant force ``q`` [N].

        ``t_start`` [s], when given, is a host's own value of the current time (equal to
        :attr:`time` to round-off of the host's clock): the step starts there, so a load
        switched by the host takes effect at the host's instant.
        """
        if t_start is None:
            t_start = self.time
        else:
            t_start = float(t_start)
            self.time = t_start
        t_end = float(t_end)
        h = t_end - t_start
        self._check_step(q, h)
        self._step_to(float(q), h, t_end)

    @staticmethod
    def _check_step(q, h) -> None:
        if not (h > 0.0 and math.isfinite(h) and math.isfinite(q)):
            raise ValueError(f"a step needs a finite q and a finite h > 0 (got q={q!r}, h={h!r})")

    def sample(self, q, times, names=OUTPUT_NAMES) -> dict:
        """Advance to each of ``times`` [s] (increasing, later than :attr:`time`) under ``q``
        [N] (constant, or ``q[k]`` over the step ending at ``times[k]``) and record the outputs
        ``names`` there.

        Returns
        -------
        dict of arrays
            One array per requested output name.
        """
        times = np.asarray(times, dtype=float)
        loads = np.broadcast_to(np.asarray(q, dtype=float), times.shape)
        rows = [OUTPUT_NAMES.index(name) for name in names]
        table = np.empty((len(rows), len(times)))
        for k, t in enumerate(times):
            self.advance_to(loads[k], t)
            out = self.outputs()
            table[:, k] = [out[row] for row in rows]
        return dict(zip(names, table))
