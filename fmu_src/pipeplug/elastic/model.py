"""Model III: pipe and plug as elastic rods with distributed Coulomb friction.

Equations (paper eqs. (12)-(14), with the outer friction docs/corrections.md D4 notes as omitted)::

    rho1 S1 u1_tt = E1 S1 u1_xx - P2 tau2 Sign(u1_t - u2_t) - P1 tau1 Sign(u1_t) chi(x)
    rho2 S2 u2_tt = E2 S2 u2_xx + P2 tau2 Sign(u1_t - u2_t)          (x in [L1-L2, L1])
    E1 S1 u1_x(0) = -Q,   all other ends free,   zero initial state

``Sign`` is set-valued at zero (static limit = sliding limit); ``chi`` = 1 on the whole pipe, or
with ``contact_growth`` on reference x >= L1 - min(max(s, 0), L1), s the front end's
displacement. Pipe and plug couple at equal reference coordinate.

Scheme: velocity-force staggered grid in space and time. Velocities live at cell centres,
axial forces at cell faces; the end faces carry the boundary forces exactly (``-Q`` and 0).
Masses are the full cells. Velocities take a kick from the force differences, then the exact
two-contact Coulomb projection node by node (:mod:`pipeplug.contact.coulomb`); the forces then
drift with the new velocities. At Courant number 1 this transports the rod's waves exactly
(d'Alembert) with no odd-even decoupling: node-centred velocities with half masses at the ends
alternate between 0 and twice the wave velocity at the struck end (docs/corrections.md D6).

Without numba the same steps run as whole-array numpy operations instead of compiled loops
(:mod:`pipeplug.elastic.vectorised`), with the same results bit for bit.

Stepping: a communication step h is taken as n = ceil(h/h_max - 1e-9) equal internal steps,
h_max = courant dx / c_fastest. The outputs follow the contract's section rule.

Exact limit: without friction, at Courant 1, the cell velocities equal the cell averages of the
d'Alembert solution at the step times; the momentum sum m v equals the impulse of Q exactly.
"""
from __future__ import annotations

import math

import numpy as np

from .. import jit
from ..interface import ModelBase, Outputs
from .grid import Section, build_grid
from .kernels import F_IN, F_OUT, K1, K2, KERNELS, M1, M2, N_ACC, W_IN, W_INNER, W_NEG, W_OUTER
from .vectorised import VECTORISED

__all__ = ["ElasticModel"]

_FIELDS = ("v1", "N1", "v2", "N2", "u1", "u2", "acc")


class ElasticModel(ModelBase):
    """Model III on the grid derived from ``params`` (see the module docstring).

    Parameters
    ----------
    params : Params
        Validated parameters (SI); ``dx`` must divide ``L1`` (and ``L2`` when the plug is
        simulated), else :class:`~pipeplug.params.ParameterError` names ``dx``.
    options : Options
        ``contact_growth`` selects the penetrated contact length of the soil friction.
    vectorised : bool, optional
        Step with whole-array numpy operations (:mod:`pipeplug.elastic.vectorised`) rather than
        the loops compiled by numba (:mod:`pipeplug.elastic.kernels`); both give the same
        numbers. By default the compiled loops when numba is enabled
        (:func:`pipeplug.jit.enabled`), else the numpy steps.
    """

    def __init__(self, params, options, vectorised: bool | None = None):
        self.params = params
        self.grid = g = build_grid(params)
        effects = (g.n2 > 0, g.soil, bool(options.contact_growth))
        self.kernel_name = KERNELS[effects].__name__
        if vectorised is None:
            vectorised = not jit.enabled()
        self.vectorised = bool(vectorised)
        self._kernel = VECTORISED[effects] if vectorised else jit.compiled(KERNELS[effects])
        self.time = 0.0
        self._dt = 0.0  # the last internal step [s] (the discrete elastic energy needs it)
        self.v1, self.N1 = np.zeros(g.n1), np.zeros(g.n1 + 1)
        self.v2, self.N2 = np.zeros(g.n2), np.zeros(g.n2 + 1)
        self.u1, self.u2 = np.zeros(g.cells1.size), np.zeros(g.cells2.size)
        self.acc = np.zeros(N_ACC)
        self._rest = None   # at_rest() of the current state, once known
        self._modes: list[tuple[int, int]] = []      # see modes()

    def steps_for(self, h: float) -> int:
        """Number of internal steps taken for a communication step ``h`` [s]."""
        return max(1, math.ceil(h / self.grid.h_max - 1e-9))

    def _step_to(self, q: float, h: float, t_end: float) -> None:
        """Advance by ``h`` [s] in equal internal steps under ``q`` [N], ending at ``t_end``
        [s]; at rest under no load the steps change nothing and are skipped."""
        if not (q == 0.0 and self.at_rest()):
            n = self.steps_for(h)
            dt = h / n
            g = self.grid
            self._kernel(n, dt, q, g.coef, self.v1, self.N1, self.v2, self.N2,
                         g.cells1, self.u1, g.cells2, self.u2, self.acc)
            self._dt = dt
            self._rest = None
            mode = self._monitor_modes()
            if not self._modes or self._modes[-1] != mode:
                self._modes.append(mode)
        self.time = t_end

    def outputs(self) -> Outputs:
        """The contract's outputs at the current time (forces of the last internal step)."""
        g, acc = self.grid, self.acc
        v_pipe = _interpolate(self.v1, g.pipe)
        u_pipe = (1.0 - g.pipe.w) * self.u1[1] + g.pipe.w * self.u1[2]
        v_plug = u_plug = 0.0
        if g.n2:
            v_plug = _interpolate(self.v2, g.plug)
            u_plug = (1.0 - g.plug.w) * self.u2[0] + g.plug.w * self.u2[1]
        outer, inner = float(acc[W_OUTER]), float(acc[W_INNER])
        return Outputs(float(v_pipe), float(v_plug), float(u_pipe), float(u_plug),
                       float(acc[F_OUT]), float(acc[F_IN]), float(acc[W_IN]), outer + inner,
                       outer, inner, self.at_rest(), *self._monitor_modes())

    def _monitor_modes(self) -> tuple[int, int]:
        """(pipe_mode, plug_mode) at the cell of x_monitor (and its plug cell)."""
        g = self.grid
        plug_mode = 0
        if g.n2:
            k = g.plug.cell
            plug_mode = _sign(self.v1[g.n1 - g.n2 + k] - self.v2[k])
        return _sign(self.v1[g.pipe.cell]), plug_mode

    def modes(self) -> tuple[tuple[int, int], ...]:
        """The modes at x_monitor after every communication step, repeats merged."""
        return tuple(self._modes)

    def at_rest(self) -> bool:
        """Every cell still, and one more internal step under Q = 0 (of the last step's
        length) leaves every field, work and force unchanged, bit for bit."""
        if self._rest is None:
            self._rest = (not self.v1.any() and not self.v2.any()
                          and self._trial_step_keeps_the_state())
        return self._rest

    def _trial_step_keeps_the_state(self) -> bool:
        """Take one step under Q = 0 on copies of the fields and compare the bits."""
        g = self.grid
        before = [getattr(self, name) for name in _FIELDS]
        after = [field.copy() for field in before]
        v1, N1, v2, N2, u1, u2, acc = after
        self._kernel(1, self._dt or g.h_max, 0.0, g.coef, v1, N1, v2, N2, g.cells1, u1,
                     g.cells2, u2, acc)
        return all(a.tobytes() == b.tobytes() for a, b in zip(before, after))

    def energies(self) -> tuple[float, float, float]:
        """Discrete energies of the scheme [J]: kinetic, elastic, and the reversing work.

        The elastic energy is sum N^n N^(n-1) / (2 E S / dx) over the inner faces (the
        staggered scheme's invariant), computed as (N^2 - (E S/dx) dt N dv) / (2 E S/dx). For
        steps of equal length, ``W_input = kinetic + elastic + W_friction + reversing`` holds to
        round-off; ``reversing`` (<= 0) is the friction work of steps in which a node's relative
        velocity changed sign, kept out of the never-decreasing ``W_friction``.
        """
        c = self.grid.coef
        kinetic = 0.5 * (c[M1] * self.v1 @ self.v1 + c[M2] * self.v2 @ self.v2)
        elastic = (_elastic_energy(self.v1, self.N1, c[K1], self._dt)
                   + _elastic_energy(self.v2, self.N2, c[K2], self._dt))
        return float(kinetic), float(elastic), float(self.acc[W_NEG])

    def get_state(self) -> dict:
        """A copy of the whole state: time, last step, fields, tracked displacements, works."""
        state = {"time": self.time, "dt": self._dt}
        state.update({name: getattr(self, name).copy() for name in _FIELDS})
        state["modes"] = np.array(self._modes, dtype=np.int64).reshape(-1, 2)
        return state

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state` (copied into this model's arrays)."""
        for name in _FIELDS:
            target = getattr(self, name)
            value = np.asarray(state[name], dtype=float)
            if value.shape != target.shape:
                raise ValueError(f"state field {name!r} has shape {value.shape}, "
                                 f"this model needs {target.shape}")
            target[...] = value
        self._rest = None
        self._modes = [tuple(map(int, row)) for row in np.asarray(state["modes"]).reshape(-1, 2)]
        self.time = float(state["time"])
        self._dt = float(state["dt"])


def _interpolate(values: np.ndarray, section: Section) -> float:
    """Linear interpolation between the two cell centres of ``section``."""
    return (1.0 - section.w) * values[section.a] + section.w * values[section.b]


def _sign(value: float) -> int:
    """-1, 0 or 1."""
    value = float(value)
    return int(value > 0.0) - int(value < 0.0)


def _elastic_energy(v: np.ndarray, N: np.ndarray, k: float, dt: float) -> float:
    """Elastic energy of one rod, sum over inner faces of N^n N^(n-1) / (2k) [J]."""
    if v.size < 2:
        return 0.0
    inner = N[1:-1]
    return float(inner @ (inner - k * dt * np.diff(v)) / (2.0 * k))
