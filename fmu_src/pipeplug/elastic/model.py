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
Masses are the full cells. The stresses reported are node-centred (the head's force, the mean of
each cell's two faces, 0 at the far end: :func:`pipeplug.elastic.cells.node_forces` says why).
Velocities take a kick from the force differences, then the exact
two-contact Coulomb projection node by node (:mod:`pipeplug.contact.coulomb`); the forces then
drift with the new velocities (:mod:`pipeplug.elastic.cells`). At Courant number 1 this
transports the rod's waves exactly (d'Alembert) with no odd-even decoupling (friction excites
one in the faces and cells, which the node-centred stresses do not carry): node-centred
velocities with half masses at the ends alternate between 0 and twice the wave velocity at the
struck end (docs/corrections.md D6).

Every internal step has the same length, ``h = courant dx / c_fastest``, on a grid of times
``t_k = t_0 + k h`` fixed when the model first steps (:class:`Clock`). The scheme conserves
the quadratic energy (per rod, ``m`` the cell mass, ``k = E S / dx``, sums over cells and inner
faces, ``N`` the forces of the half step ahead)::

    E = sum m v^2 / 2 + sum N (N - k h D v) / (2 k)
      = [sum m v^2 / 2 - (k h^2 / 8) sum (D v)^2]  +  sum Nbar^2 / (2 k),   Nbar = N - k h D v / 2

(``D v`` the velocity differences across the inner faces): the first bracket is ``E_kinetic``,
>= 0 for Courant numbers <= 1, the second ``E_strain``, >= 0 always (``Nbar`` is the force at
the step's time). Each step adds the input work ``Q h (v0 + v0') / 2`` and removes the friction
work, never negative at either contact (:func:`pipeplug.elastic.cells.limit`), so ``W_input = E_kinetic +
E_strain + W_friction`` holds to round-off, and ``E`` is bounded by the input work: the scheme
cannot diverge. A step of another length would conserve another energy, and alternating
lengths would pump the grid's shortest waves (at Courant 1 their energy is a small difference of
large terms); that is why the length never changes. Without numba the same steps run as
whole-array numpy operations instead of compiled loops (:mod:`pipeplug.elastic.vectorised`),
with the same results bit for bit.

Stepping a communication step: the grid points up to its end are stepped; a communication point
between grid points keeps the impulse of Q since the last one for the next step, which applies
the mean force of its whole interval (the impulse is exact; the load's timing is resolved to
``h``). The outputs are those of the last grid point at or before the communication point.
Communication steps that are multiples of ``h`` therefore take exactly the grid's steps.

Exact limit: without friction, at Courant 1, the cell velocities equal the cell averages of the
d'Alembert solution at the grid times; the momentum sum m v equals the impulse of Q exactly.
"""
from __future__ import annotations

import math

import numpy as np

from .. import jit
from ..contact.face import sign
from ..interface import ModelBase, Outputs, profile_sections
from ..params import ParameterError
from .cells import accumulate, node_forces
from .grid import Section, build_grid
from .head import cushion_energy, start_strike
from .kernels import (
    COMPENSATION,
    DX,
    F_IN,
    F_OUT,
    GROWTH,
    K1,
    K2,
    K_UNLOAD,
    KERNELS,
    M1,
    M2,
    N_ACC,
    N_MAX,
    N_MIN,
    RAM,
    RAM_MASS,
    W_CUSHION,
    W_CUSHION_ERROR,
    W_DAMPING,
    W_DAMPING_ERROR,
    W_FACE,
    W_FACE_ERROR,
    W_IN,
    W_INNER,
    W_OUTER,
    W_RAM,
)
from .vectorised import VECTORISED

__all__ = ["ElasticModel", "Clock"]

_FIELDS = ("v1", "N1", "v2", "N2", "u1", "u2", "acc")
#: A communication point within this share of ``h`` of a grid point is on it (host clocks carry
#: round-off; the load's timing error is then at most this share of a step).
SNAP = 1e-6


class Clock:
    """The elastic model's grid of times and the load's impulse since its last point.

    Grid points are ``origin + k h``; ``pending`` is the impulse of Q [N s] from grid point
    ``k`` to :attr:`time` (0 when the time is at or, by round-off, before the point). It is
    kept as runs of one force each, ``pending_load`` the last run's force from ``run_start``
    [s] and ``closed`` [N s] the impulse of the runs before it (``mixed``: there were some; a
    flag, not a NaN, so that a state holds only finite numbers). A run's impulse is its force
    times its length in one product, whatever points the host put in it, so that the
    impulse, and with it every result, is the same on every host grid that holds the load's
    edges (a sum over the host's sub-steps would round differently on each, and a friction
    contact at its limit may turn on the last bit). A step whose load did not change over it
    takes that force itself, not the mean its impulse would give to round-off, so that every
    host grid gives the grid points' results bit for bit.
    """

    def __init__(self, h: float):
        self.h = h
        self.origin = 0.0      #: the first step's start [s]
        self.started = False   #: the origin is fixed (the time was set once)
        self.k = 0             #: grid points stepped
        self.pending = 0.0     #: [N s]
        self.pending_load = 0.0  #: the last run's force [N]
        self.run_start = 0.0   #: the last run's start [s]
        self.closed = 0.0      #: the impulse of the runs before it [N s]
        self.mixed = False     #: the pending impulse came from different forces
        self.time = 0.0        #: the model's time [s]

    def point(self, k: int) -> float:
        """Grid point ``k`` [s]."""
        return self.origin + k * self.h

    def last_point_by(self, t: float) -> int:
        """The index of the last grid point at or before ``t`` [s] (to within :data:`SNAP`)."""
        return max(self.k, math.floor((t - self.origin) / self.h + SNAP))

    def first_load(self, q: float) -> float:
        """The force [N] of the step from grid point ``k`` when ``q`` [N] acts from the time
        on: ``q`` itself if it acted since the point, else the mean force of the interval."""
        if self.time <= self.point(self.k) or (not self.mixed and self.pending_load == q):
            return q
        end = self.point(self.k + 1)
        if q == self.pending_load:              # the last run goes on to the step's end
            return (self.closed + q * (end - self.run_start)) / self.h
        return (self.pending + q * (end - self.time)) / self.h

    def hold(self, q: float, t_end: float) -> None:
        """Keep the impulse of ``q`` [N] from the time (or grid point ``k``) to ``t_end``
        [s] for the next step, and move the time there."""
        start = max(self.time, self.point(self.k))
        if t_end > start:
            if self.time <= self.point(self.k):
                self.closed, self.run_start, self.pending_load, self.mixed = 0.0, start, q, False
            elif self.pending_load != q:        # a new run: the last one closes here
                self.closed += self.pending_load * (start - self.run_start)
                self.run_start, self.pending_load, self.mixed = start, q, True
            self.pending = self.closed + q * (t_end - self.run_start)
        self.time = t_end

    def passed(self, k_end: int) -> None:
        """Grid points up to ``k_end`` were stepped: nothing pending."""
        self.k, self.pending, self.pending_load, self.mixed = k_end, 0.0, 0.0, False
        self.run_start, self.closed = 0.0, 0.0


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

    def __init__(self, params, options, vectorised: bool | None = None,
                 profile_points: int = 0):
        self.params = params
        self.grid = g = self._build_grid(params, profile_points)
        if profile_points:
            self._profiler = _profiles
        if vectorised is None:
            vectorised = not jit.enabled()
        self.vectorised = bool(vectorised)
        self._kernel = self._choose_kernel(options, self.vectorised)
        self.clock = Clock(g.h_max)
        self._max_steps = params.max_internal_steps
        self.v1, self.N1 = np.zeros(g.n1), np.zeros(g.n1 + 1)
        self.v2, self.N2 = np.zeros(g.n2), np.zeros(g.n2 + 1)
        self.u1, self.u2 = np.zeros(g.cells1.size), np.zeros(g.cells2.size)
        self.acc = np.zeros(N_ACC)
        self._rest = None   # at_rest() of the current grid state, once known
        self._modes: list[tuple[int, int]] = []      # see modes()

    def _build_grid(self, params, profile_points: int):
        """The grid (:func:`pipeplug.elastic.grid.build_grid`)."""
        return build_grid(params, profile_points)

    def _choose_kernel(self, options, vectorised: bool):
        """The one kernel of the effects the grid and options call for (and its name in
        :attr:`kernel_name`)."""
        g = self.grid
        if self.params.has_damping:   # one kernel, loops only (pipeplug.elastic.damped)
            from .damped import run_damped
            g.coef[GROWTH] = float(options.contact_growth)
            self.kernel_name = run_damped.__name__
            return run_damped if vectorised else jit.compiled(run_damped)
        if self.params.has_face:      # one kernel, loops only (pipeplug.elastic.face)
            from .face import run_face
            g.coef[GROWTH] = float(options.contact_growth)
            self.kernel_name = run_face.__name__
            return run_face if vectorised else jit.compiled(run_face)
        effects = (g.n2 > 0, g.soil, bool(options.contact_growth))
        self.kernel_name = KERNELS[effects].__name__
        return VECTORISED[effects] if vectorised else jit.compiled(KERNELS[effects])

    @property
    def time(self) -> float:
        """The model's time [s] (the host's last communication point)."""
        return self.clock.time

    @time.setter
    def time(self, value: float) -> None:
        clock = self.clock
        if not clock.started:
            # The grid starts where the first step starts, and stays there: a grid that
            # followed the time while nothing happened would differ between host grids
            # once a strike at the start acts.
            clock.origin, clock.started = value, True
        clock.time = value

    def steps_for(self, h: float) -> int:
        """Number of internal steps a communication step of ``h`` [s] from the current time
        takes (grid points it passes)."""
        return self.clock.last_point_by(self.clock.time + h) - self.clock.k

    def _step_to(self, q: float, h: float, t_end: float) -> None:
        """Step the grid points up to ``t_end`` [s] under ``q`` [N] (the first with the
        impulse pending since the last point); keep the impulse beyond the last one."""
        clock = self.clock
        k_end = clock.last_point_by(t_end)
        n = k_end - clock.k
        if n and not (q == 0.0 and clock.pending == 0.0 and self.at_rest()):
            self._check_count(n, h)
            self.acc[N_MIN], self.acc[N_MAX] = math.inf, -math.inf
            self._steps(1, clock.first_load(q))
            if n > 1:
                self._steps(n - 1, q)
            mode = self._monitor_modes()
            if not self._modes or self._modes[-1] != mode:
                self._modes.append(mode)
        elif n:
            self._rest_for(n)
        if n:
            clock.time = max(clock.time, clock.point(k_end))
            clock.passed(k_end)
        clock.hold(q, t_end)

    def _rest_for(self, n: int) -> None:
        """``n`` internal steps at rest: the forces hold; a ram leaving the head flies on
        (its compression shrinks at its velocity, which nothing changes)."""
        acc = self.acc
        nodes = node_forces(self.N1)
        acc[N_MIN], acc[N_MAX] = float(nodes.min()), float(nodes.max())
        if acc[RAM]:
            acc[RAM + 1] = _fly(acc[RAM + 1], self.clock.h * (acc[RAM] - self.v1[0]), n)

    def strike(self, velocity: float) -> None:
        """Start a strike now: the ram at the head, touching an unloaded cushion, moving at
        ``velocity`` [m/s] (it acts from the next internal step, within h_max).

        Raises
        ------
        ParameterError
            Without a ram (``ram_mass = 0``), or for a velocity that is not finite or whose
            kinetic energy is not.
        """
        if not self.params.has_ram:
            raise ParameterError("strikes", "an increase", "none without a ram (ram_mass > 0)")
        acc, mass = self.acc, self.grid.coef[RAM_MASS]
        self._check_strike(velocity, float(mass))
        # The ram's kinetic energy is replaced. What the cushion still held, R >= 0, is lost
        # with it (W_cushion = work on the cushion - R rises by R once R is 0). R < 0 (the step
        # of pull after a separation, a push closing fast): energy the bodies hold beyond the
        # scheme's (the force acted over the whole step), which the next steps would have
        # taken back. The strike cancels them, so the bodies keep it: the strike brought it
        # (W_RAM), and the work on the cushion takes -R so that W_cushion does not change
        # (pipeplug.elastic.head).
        held = self._cushion_energy()
        acc[W_RAM] += 0.5 * mass * (velocity * velocity - acc[RAM] ** 2) - min(held, 0.0)
        if held < 0.0:
            accumulate(acc, W_CUSHION, W_CUSHION_ERROR, -held)
        start_strike(acc[RAM:RAM + 6], float(velocity))
        self._rest = None

    def _cushion_energy(self) -> float:
        """The cushion's recoverable energy now [J] (0 without a ram)."""
        acc = self.acc
        return cushion_energy(acc[RAM + 3], acc[RAM], self.v1[0], self.grid.coef[K_UNLOAD],
                              self.clock.h) if acc[RAM + 3] else 0.0

    def _check_count(self, n: int, h: float) -> None:
        """Refuse a communication step of more than ``max_internal_steps`` internal steps."""
        if n > self._max_steps:
            raise ParameterError(
                "communicationStepSize", h,
                f"at most max_internal_steps = {self._max_steps:g} internal steps of "
                f"{self.clock.h!r} s while the pipe moves (raise max_internal_steps to allow "
                f"longer steps)")

    def _steps(self, n: int, q: float) -> None:
        """``n`` internal steps under ``q`` [N]."""
        g = self.grid
        self._kernel(n, self.clock.h, q, g.coef, self.v1, self.N1, self.v2, self.N2, g.cells1,
                     self.u1, g.cells2, self.u2, self.acc)
        self._rest = None

    def outputs(self) -> Outputs:
        """The contract's outputs at the last grid point (forces of its internal step)."""
        g, acc = self.grid, self.acc
        v_pipe = _interpolate(self.v1, g.pipe)
        u_pipe = _tracked(self.u1, 1, g.pipe)
        v_plug, u_plug = self._plug_motion()
        outer, inner = _work(acc, W_OUTER), _work(acc, W_INNER)
        kinetic, strain = self.energies()
        w_input = _work(acc, W_IN)
        area = self.params.S1
        if self.params.has_ram:
            ram = (float(acc[RAM]), float(acc[W_RAM]),
                   float(acc[W_CUSHION] + acc[W_CUSHION_ERROR]) - self._cushion_energy(),
                   float(acc[RAM + 4] + acc[RAM + 5]))
        else:
            ram = (0.0, 0.0, 0.0, w_input)
        return Outputs(float(v_pipe), float(v_plug), float(u_pipe), float(u_plug),
                       float(acc[F_OUT]), float(acc[F_IN]), w_input, outer + inner,
                       outer, inner, kinetic, strain, 0.0, float(-self.N1[0]), *ram,
                       float(self.N1[0]) / area, float(acc[N_MIN]) / area,
                       float(acc[N_MAX]) / area, self.at_rest(), *self._monitor_modes(),
                       float(acc[W_FACE] + acc[W_FACE_ERROR]),
                       float(acc[W_DAMPING] + acc[W_DAMPING_ERROR]), *self._plug_length())

    def _plug_motion(self) -> tuple[float, float]:
        """(v_plug [m/s], u_plug [m]) at the plug section of x_monitor (0 without a plug)."""
        g = self.grid
        if not g.n2:
            return 0.0, 0.0
        return (float(_interpolate(self.v2, g.plug)),
                float(_tracked(self.u2, 0, g.plug)))

    def _plug_length(self) -> tuple[float, float, float]:
        """(L2_now [m], W_accretion [J], W_removed [J]): the plug keeps its length."""
        return float(self.params.L2), 0.0, 0.0

    def _monitor_modes(self) -> tuple[int, int]:
        """(pipe_mode, plug_mode) at the cell of x_monitor (and its plug cell)."""
        g = self.grid
        plug_mode = 0
        if g.n2:
            k = g.plug.cell
            plug_mode = sign(self.v1[g.n1 - g.n2 + k] - self.v2[k])
        return sign(self.v1[g.pipe.cell]), plug_mode

    def modes(self) -> tuple[tuple[int, int], ...]:
        """The modes at x_monitor after every communication step, repeats merged."""
        return tuple(self._modes)

    def at_rest(self) -> bool:
        """No impulse pending, every cell still, and one more internal step under Q = 0 leaves
        every field, work and force unchanged, bit for bit; a ram is off the head and not
        coming back (no cushion force, not moving forward: nothing it does reaches the
        pipe, whose head is still)."""
        if self._rest is None:
            self._rest = (not self.v1.any() and not self.v2.any() and self._ram_gone()
                          and self._trial_step_keeps_the_state())
        return self._rest and self.clock.pending == 0.0

    def _ram_gone(self) -> bool:
        acc = self.acc
        return acc[RAM + 3] == 0.0 and acc[RAM] <= 0.0

    def _trial_step_keeps_the_state(self) -> bool:
        """Take one step under Q = 0 on copies of the fields and compare the bits (but the
        flight of a ram gone, :meth:`_rest_for`)."""
        g = self.grid
        before = [getattr(self, name) for name in _FIELDS]
        after = [field.copy() for field in before]
        v1, N1, v2, N2, u1, u2, acc = after
        self._kernel(1, self.clock.h, 0.0, g.coef, v1, N1, v2, N2, g.cells1, u1, g.cells2, u2,
                     acc)
        acc[RAM + 1] = self.acc[RAM + 1]
        return all(a.tobytes() == b.tobytes() for a, b in zip(before, after))

    def energies(self) -> tuple[float, float]:
        """The scheme's kinetic and strain energy at the last grid point [J] (module docstring),
        both >= 0, with the ram's kinetic energy and the cushion's recoverable energy
        (:mod:`pipeplug.elastic.head`, split as a face of the rods: the cross term of its
        modified energy in the kinetic part); ``W_input + W_ram = kinetic + strain +
        W_friction + W_cushion`` to round-off."""
        c, h, acc = self.grid.coef, self.clock.h, self.acc
        pipe = _rod_energies(self.v1, self.N1, c[M1], c[K1], h)
        plug = self._plug_energies()
        kinetic, strain = pipe[0] + plug[0], pipe[1] + plug[1]
        if self.params.has_ram:
            kinetic += 0.5 * c[RAM_MASS] * acc[RAM] ** 2
            force = acc[RAM + 3]
            if force:
                closing = acc[RAM] - self.v1[0]
                kinetic -= 0.125 * c[K_UNLOAD] * h * h * closing * closing
                at_step = force - 0.5 * c[K_UNLOAD] * h * closing
                strain += at_step * at_step / (2.0 * c[K_UNLOAD])
        return float(kinetic), float(strain)

    def _plug_energies(self) -> tuple[float, float]:
        """The plug's kinetic and strain energy [J] (:func:`_rod_energies`)."""
        c = self.grid.coef
        return _rod_energies(self.v2, self.N2, c[M2], c[K2], self.clock.h)

    def get_state(self) -> dict:
        """A copy of the whole state: clock, fields, tracked displacements, works."""
        clock = self.clock
        state = {"time": clock.time, "origin": clock.origin, "started": clock.started,
                 "k": clock.k,
                 "pending": clock.pending, "pending_load": clock.pending_load,
                 "run_start": clock.run_start, "closed": clock.closed, "mixed": clock.mixed}
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
        clock = self.clock
        clock.time, clock.origin = float(state["time"]), float(state["origin"])
        clock.started = bool(state["started"])
        clock.k, clock.pending = int(state["k"]), float(state["pending"])
        clock.pending_load = float(state["pending_load"])
        clock.run_start, clock.closed = float(state["run_start"]), float(state["closed"])
        clock.mixed = bool(state["mixed"])


#: steps of a ram's flight added at once (memory of one chunk: 8 x this bytes)
_FLIGHT_CHUNK = 1 << 16


def _fly(delta: float, step: float, n: int) -> float:
    """``delta`` [m] after ``n`` additions of ``step`` [m], one at a time, as ``n`` internal
    steps add them: the same bits on every host grid (``n * step`` in one product would round
    otherwise, and the moment a pulled pipe meets the ram again would depend on how the host
    stepped)."""
    while n > 0:
        m = min(n, _FLIGHT_CHUNK)
        chunk = np.full(m + 1, step)
        chunk[0] = delta
        delta = float(np.add.accumulate(chunk)[-1])
        n -= m
    return delta


def _work(acc, index) -> float:
    """A compensated sum of ``acc`` [J]: the sum and its accumulated rounding error."""
    return float(acc[index] + acc[index + COMPENSATION])


def _profiles(model: ElasticModel) -> tuple:
    """The profiles (:data:`pipeplug.interface.PROFILES`) of ``model``: each element as
    :meth:`ElasticModel.outputs` computes the output at its section; the stress linearly
    between the pipe's node-centred forces (:func:`pipeplug.elastic.cells.node_forces`: the
    head's at x = 0, each cell's at its centre, the far end's at x = L1)."""
    g, u1 = model.grid, model.u1
    v = np.array([_interpolate(model.v1, s) for s in g.profile])
    u = np.array([_tracked(u1, 4 + 3 * k, s) for k, s in enumerate(g.profile)])
    dx, n1 = g.coef[DX], g.n1
    nodes = np.concatenate(([0.0], (np.arange(n1) + 0.5) * dx, [n1 * dx]))
    x = profile_sections(model.params.L1, model.params.L2, len(g.profile))[0]
    stress = np.interp(x, nodes, node_forces(model.N1)) / model.params.S1
    plug = (np.array([_interpolate(model.v2, s) for s in g.profile_plug]) if g.n2
            else np.zeros(len(g.profile)))
    return v, u, stress, plug


def _interpolate(values: np.ndarray, section: Section) -> float:
    """The value of the cells' ``values`` at ``section`` (its cells' weighted sum)."""
    (a, b, c), (wa, wb, wc) = section.cells, section.weights
    return wa * values[a] + wb * values[b] + wc * values[c]


def _tracked(u: np.ndarray, first: int, section: Section) -> float:
    """The displacement [m] at ``section`` from the displacements ``u`` of the tracked cells,
    its three cells' from index ``first`` on."""
    wa, wb, wc = section.weights
    return wa * u[first] + wb * u[first + 1] + wc * u[first + 2]


def _rod_energies(v: np.ndarray, N: np.ndarray, m: float, k: float, h: float) -> tuple:
    """Kinetic and strain energy of one rod [J] (module docstring): velocities ``v`` [m/s] of
    cells of mass ``m`` [kg], forces ``N`` [N] of the half step ahead at its faces, stiffness
    ``k = E S / dx`` [N/m], internal step ``h`` [s]."""
    if v.size == 0:
        return 0.0, 0.0
    # called after every communication step: slices and np.dot (the same values as np.diff and
    # @, a third of their call overhead on arrays this small)
    dv = v[1:] - v[:-1]
    at_step = N[1:-1] - (0.5 * k * h) * dv
    return (float(0.5 * m * np.dot(v, v) - (0.125 * k * h * h) * np.dot(dv, dv)),
            float(np.dot(at_step, at_step) / (2.0 * k)))
