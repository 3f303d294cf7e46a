"""Exact event-driven solver of the rigid models I and II (to round-off).

Equations (paper eqs. (1)-(3) and (11), docs/corrections.md A6, B4, C7/C8)::

    M1 U1'' = Q + f1 + f2,      M2 U2'' = -f2
    f1 in -P1 Lc tau1 Sign(U1'),   f2 in -P2 L2 tau2 Sign(U1' - U2')

with ``Lc = L1`` (model I) or ``Lc = min(max(U1, 0), L1)`` (model II, ``contact_growth``), and
Sign(0) = [-1, 1] (static limit = sliding limit). Q is constant over each step. Between events
the motion is closed-form (:mod:`pipeplug.rigid.pieces`); at each event the contact modes are
chosen by solving both contacts jointly (:func:`pipeplug.contact.coulomb.two_contacts`).
Exact solution for a rectangular pulse: the closed form of model I, domains I-V.

Energy: W_input = kinetic energy + W_friction holds to round-off.

A ram (``ram_mass > 0``) strikes the head through a cushion or directly (:meth:`RigidExact.strike`);
its pieces are closed-form too (:mod:`pipeplug.rigid.ram`) for model I (constant soil friction,
or none), and with W_ram and the cushion's energy the ledger still closes to round-off. Model II
with a ram (``contact_growth`` with ``tau1 > 0``) is refused when the model is built
(:func:`pipeplug.build_model`): the growing friction and the cushion make two coupled
frequencies, not in closed form.

The solver is one source of functions over two records (:mod:`pipeplug.rigid.record`,
:mod:`pipeplug.rigid.stepping`), run compiled by numba when it is available (cached on disk,
:mod:`pipeplug.jit`) or as plain Python; both give the same numbers.
"""
from __future__ import annotations

import math
from functools import cache

import numpy as np

from .. import jit
from ..interface import GROWTH_OUTPUTS, OUTPUT_NAMES, ModelBase, Outputs
from ..params import PARAMETERS, ParameterError, check_rules, values_record
from . import ramstep, stepping
from .record import (
    BUILT,
    D0,
    DMAX,
    END,
    ERROR,
    EXT_T,
    HORIZON,
    KICK,
    KICK1,
    LOGGED,
    MODE,
    N_HIGH,
    N_LOW,
    N_PAR,
    P_M1,
    P_M2,
    P_RAM_M,
    RAM_ON,
    STEPPING,
    T0,
    TIME,
    U1,
    U2,
    V1,
    V2,
    VR,
    VSCALE,
    W_CUSH,
    W_FACE,
    W_IN,
    W_INNER,
    W_OUTER,
    W_RAM,
    ZW,
    Q,
    as_array,
    parameter_record,
    record_into,
    state_record,
)

__all__ = ["RigidExact", "compiled_model", "KERNELS", "RAM_KERNELS"]

#: the entry points of the solver (compiled together when numba is used)
KERNELS = (stepping.step_to, stepping.start_piece, stepping.sample_into, stepping.outputs_at)
#: those of a model with a ram, and its strike
RAM_KERNELS = (ramstep.ram_step_to, ramstep.ram_start_piece, ramstep.ram_sample_into,
               ramstep.ram_outputs_at, ramstep.strike)
_STATE_KEYS = ("time", "t0", "U1", "V1", "U2", "V2", "W_in", "W_outer", "W_inner", "Q", "kick",
               "horizon")
_STATE_SLOTS = (TIME, T0, U1, V1, U2, V2, W_IN, W_OUTER, W_INNER, Q, KICK, HORIZON)
#: the ram's part of the state (models with a ram): its origin values and the last step's
#: extremes of the axial force
_RAM_KEYS = ("ram_on", "delta", "v_ram", "delta_max", "W_ram", "W_cushion", "v_scale", "kick1",
             "zeno_w", "n_low", "n_high")
_RAM_SLOTS = (RAM_ON, D0, VR, DMAX, W_RAM, W_CUSH, VSCALE, KICK1, ZW, N_LOW, N_HIGH)


_FRESH_LIST = state_record()           # a fresh model's state, as each path holds it
_FRESH = as_array(_FRESH_LIST)
_LOG_SIZE = 64                          # mode codes the solver logs between two takings
_PATHS: dict = {}                       # compiled (bool) -> the entry points to run


def _kernels(compiled: bool, ram: bool = False) -> tuple:
    """The solver's entry points (:data:`RAM_KERNELS` with a ``ram``): compiled when asked
    and numba is available (imported now), else the plain functions themselves."""
    key = (compiled, ram)
    if key not in _PATHS:
        plain = RAM_KERNELS if ram else KERNELS
        fns = tuple(jit.compiled(f) for f in plain) if compiled else plain
        _PATHS[key] = plain if all(a is b for a, b in zip(fns, plain)) else fns
    return _PATHS[key]


_FLOAT64 = np.dtype(np.float64)        # numpy's one instance of the native float64 dtype
_NO_GROUPS = frozenset()               # the rigid exact solver checks no conditional group
_L2_DEFAULT = next(p.default for p in PARAMETERS if p.name == "L2")
_NONE: dict = {}                        # no parameter given


@cache
def _path(compiled: bool, ram: bool) -> dict:
    """The attributes a model on a path has in common: ``compiled`` (True when running
    compiled code, else the plain functions themselves), ``has_ram`` (a ram strikes the head:
    :meth:`RigidExact.strike`) and the solver's entry points; set at once per build."""
    fns = _kernels(compiled, ram)
    return {"compiled": fns is not (RAM_KERNELS if ram else KERNELS), "has_ram": ram,
            "_step": fns[0], "_start": fns[1], "_sample": fns[2], "_outputs": fns[3],
            "_strike": fns[4] if ram else None,
            "_rest": ramstep.ram_at_rest if ram else stepping.at_rest}


#: what a compiled build needs, found at its first call (:func:`_common_path`): the compiled
#: :func:`~pipeplug.rigid.record.record_into` and the checks' arrays; False without numba
_COMMON: tuple | bool | None = None


def _common_path() -> tuple | bool:
    """Set up the common path, compiled and without a ram, once: :class:`RigidExact` holds its
    attributes (:func:`_path`) as class attributes, so that a model built on it sets its own
    arrays alone (a model on another path sets them on itself, over the class's). Returns
    :data:`_COMMON`."""
    global _COMMON
    if _COMMON is None:
        path = _path(True, False)
        if path["compiled"]:
            # The two calls of every case, stepping and dense output, skip numba's dispatch:
            # the model passes them the types of these examples alone (arrays it made, floats,
            # and times and loads as _floats makes them, 1-D as sample checks).
            st, par, log, rows = _FRESH.copy(), np.zeros(N_PAR), np.zeros(_LOG_SIZE), np.zeros(1)
            path = dict(path, _step=_Specialised(stepping.step_to, st, par, log, 0.0, 0.0),
                        _sample=_Specialised(stepping.sample_into, st, par, log, rows, rows,
                                             np.zeros((4, 1)), 0))
            for name, value in path.items():
                if isinstance(value, _Specialised):
                    value.__set_name__(RigidExact, name)
                elif callable(value):
                    value = staticmethod(value)
                setattr(RigidExact, name, value)
            rules, limits = check_rules(_NO_GROUPS)
            flat, record = values_record(_NONE)
            _COMMON = (jit.specialised(record_into, par, flat, record, rules, limits, False),
                       rules, limits)
        else:
            _COMMON = False
    return _COMMON


class _Specialised:
    """A class attribute of :class:`RigidExact`: ``kernel`` compiled for the argument types of
    ``examples`` (:func:`~pipeplug.jit.specialised`) when a model first reads it, which then
    takes its place on the class (a model that only steps compiles, or loads from the cache,
    no dense output)."""

    def __init__(self, kernel, *examples):
        self.kernel, self.examples = kernel, examples

    def __set_name__(self, owner, name):
        self.name = name

    def __get__(self, model, owner):
        function = jit.specialised(self.kernel, *self.examples)
        setattr(owner, self.name, staticmethod(function))
        return function


def _floats(values) -> np.ndarray:
    """``values`` as a writable contiguous float64 array (the type the compiled code takes),
    without a copy when they are one already."""
    # carray: C-contiguous, aligned and writeable, all that numba's type of it records
    if type(values) is np.ndarray and values.dtype is _FLOAT64 and values.flags.carray:
        return values                    # the common case, without numpy's conversion call
    array = np.ascontiguousarray(values, dtype=np.float64)
    return array if array.flags.writeable else array.copy()


def _rows(names) -> tuple[list[int], int, bool]:
    """The rows of ``names`` in the outputs' table, the rows a dense output fills (the
    kinematics alone, the first four outputs, need no forces or works) and whether the names
    are those rows in order: found once per tuple of names."""
    try:
        return _ROWS[names]
    except (KeyError, TypeError):        # new, or not hashable (a list)
        rows = [OUTPUT_NAMES.index(name) for name in names]
        filled = 4 if max(rows) < 4 else _SOLVED
        found = rows, filled, rows == list(range(filled))
        if type(names) is tuple:
            _ROWS[names] = found
        return found


_ROWS: dict[tuple, tuple[list[int], int, bool]] = {}
#: the outputs the solver's functions compute (the rest, GROWTH_OUTPUTS, are constants here)
_SOLVED = OUTPUT_NAMES.index(GROWTH_OUTPUTS[0])


class RigidExact(ModelBase):
    """Rigid pipe (and plug), exact stepping. See the module docstring.

    Parameters
    ----------
    params : Params
        Validated parameters.
    options : Options
        ``contact_growth`` selects model II; ``solver`` must be ``"exact"``.
    compiled : bool, optional
        Run the compiled functions when numba is available (default), else plain Python.
    """

    def __init__(self, params, options, compiled: bool = True):
        self._setup(parameter_record(params, options.contact_growth), float(params.L2),
                    _path(compiled, bool(params.has_ram)))

    def _setup(self, par, L2: float, path: dict) -> None:
        """Hold the constants ``par`` (a list, or an array when compiled) of a model with the
        plug length ``L2`` [m] on a path (:func:`_path`)."""
        self.__dict__.update(path)
        self._constant = (L2, 0.0, 0.0)             # L2_now, W_accretion, W_removed
        if path["compiled"]:
            self._par = par if type(par) is np.ndarray else as_array(par)
            self._st, self._log = _FRESH.copy(), np.zeros(_LOG_SIZE)
        else:
            self._par, self._st, self._log = par, list(_FRESH_LIST), [0.0] * _LOG_SIZE
        self._modes: list[tuple[int, int]] = []     # taken from the log; see modes()

    @property
    def M1(self) -> float:
        """Pipe mass [kg]."""
        return float(self._par[P_M1])

    @property
    def M2(self) -> float:
        """Plug mass [kg] (0 without a plug)."""
        return float(self._par[P_M2])

    @property
    def time(self) -> float:
        """The model's time [s]."""
        return float(self._st[TIME])

    @time.setter
    def time(self, value: float) -> None:
        self._st[TIME] = value

    def _step_to(self, q: float, h: float, t_end: float) -> None:
        """Advance to ``t_end`` [s] under a constant struck-end force ``q`` [N] (events are
        times, so only ``t_end`` matters)."""
        code = self._step(self._st, self._par, self._log, q, t_end)
        rounds = 0
        while code == stepping.LOG_FULL:
            rounds = self._count_round(rounds, 1)
            code = self._step(self._st, self._par, self._log, q, t_end)
        if code:
            self._raise(code)

    def _count_round(self, rounds: int, steps: int) -> int:
        """Take the full log (:meth:`_take_log`) and count the call of a solver function that
        filled it: each filled it with ``_LOG_SIZE`` pieces, so after
        ``MAX_EVENTS_PER_STEP / _LOG_SIZE`` calls per step (``steps`` steps) the step has too
        many events (the function's own count restarts with each call, which would let
        events that keep changing the modes run without end)."""
        self._take_log()
        rounds += 1
        if rounds * _LOG_SIZE > stepping.MAX_EVENTS_PER_STEP * steps:
            self._raise(stepping.TOO_MANY_EVENTS)
        return rounds

    def _take_log(self) -> None:
        """Move the mode codes the solver logged into :attr:`_modes` (the solver merged
        repeats), emptying its log."""
        st = self._st
        self._modes.extend(map(stepping.mode_of, self._log[:int(st[LOGGED])]))
        st[LOGGED] = 0.0

    def _raise(self, code: int) -> None:
        """Raise the failure a solver function reported."""
        if code == stepping.TOO_MANY_EVENTS:
            raise RuntimeError(f"more than {stepping.MAX_EVENTS_PER_STEP} friction events in "
                               f"one step")
        if code == stepping.LOAD_NOT_FINITE:
            raise ValueError("a step needs a finite load q")
        if code == stepping.SEGMENT_MISSED:
            if not math.isfinite(self._st[ERROR]):   # not a missed event: beyond float range
                raise OverflowError(f"the pipe's displacement U1 = {float(self._st[ERROR])!r} m")
            raise RuntimeError(f"segment event at U1 = {float(self._st[ERROR])!r} m, "
                               f"{float(self._st[END])!r} m expected")

    def sample(self, q, times, names=OUTPUT_NAMES) -> dict:
        """Dense output: advance through ``times``, recording outputs there.

        Each piece is evaluated once for all the sample times it covers, so a long record
        costs about as much as its events. Same values as :meth:`advance_to` each time
        followed by :meth:`outputs`.

        Parameters
        ----------
        q : float or array of float
            Struck-end force [N]: constant, or ``q[j]`` over the interval ending at
            ``times[j]``.
        times : array of float
            Increasing absolute times [s], all later than the current time.
        names : sequence of str, optional
            The outputs to record (default: all of :class:`~pipeplug.model.Outputs`).

        Returns
        -------
        dict of arrays
            One array per requested output name.
        """
        times, loads = _floats(times), _floats(q)
        if times.ndim != 1:                 # the compiled call takes 1-D times alone
            raise ValueError(f"times must be 1-D (got {times.ndim} dimensions)")
        if loads.shape != times.shape:
            loads = np.broadcast_to(loads, times.shape).copy()
        rows, filled, in_order = _rows(names)
        # The kinematics' rows are written in every column (or an error raised); of all the
        # outputs' rows, W_damping's is not (0 here).
        table = (np.empty if filled == 4 else np.zeros)((filled, len(times)))
        code, done = self._sample(self._st, self._par, self._log, loads, times, table, 0)
        rounds = 0
        while code == stepping.LOG_FULL:
            rounds = self._count_round(rounds, len(times))
            code, done = self._sample(self._st, self._par, self._log, loads, times, table, done)
        if code:
            self._raise(code)
        if in_order:                        # the table's rows are the outputs asked for
            return dict(zip(names, table))
        return {name: table[row] if row < _SOLVED else np.full(len(times),
                                                              self._constant[row - _SOLVED])
                for name, row in zip(names, rows)}

    def outputs(self) -> Outputs:
        """The contract's outputs at the current time."""
        out = self._outputs(self._st, self._par, self._st[TIME])
        return Outputs._make((*out[:21], out[21] != 0.0, int(out[22]), int(out[23]),
                              out[24], 0.0, *self._constant))   # W_damping: 0 here

    def at_rest(self) -> bool:
        """Both bodies stuck with no load (and a ram off the head, not coming back): a step
        under Q = 0 changes no output."""
        return bool(self._rest(self._st))

    def strike(self, velocity: float) -> None:
        """Start a strike now: the ram at the head, touching an unloaded cushion, moving at
        ``velocity`` [m/s] (a direct strike faster than the head hits it at once).

        Raises
        ------
        ParameterError
            Without a ram (``ram_mass = 0``), or for a velocity that is not finite or whose
            kinetic energy is not.
        """
        if not self.has_ram:
            raise ParameterError("strikes", "an increase", "none without a ram (ram_mass > 0)")
        self._check_strike(velocity, float(self._par[P_RAM_M]))
        self._take_log()                # room for the strike's piece
        self._strike(self._st, self._par, self._log, float(velocity))

    def modes(self) -> tuple[tuple[int, int], ...]:
        """Every piece's contact modes (pipe_mode, plug_mode) in order, repeats merged."""
        self._take_log()
        return tuple(self._modes)

    def get_state(self) -> dict:
        """The whole state: the current piece's origin, its force and search horizon, and the
        modes gone through."""
        state = {k: float(self._st[i]) for k, i in zip(_STATE_KEYS, _STATE_SLOTS)}
        state["kick"] = int(state["kick"])
        state["W_face"] = float(self._st[W_FACE])
        if self.has_ram:
            state.update({k: float(self._st[i]) for k, i in zip(_RAM_KEYS, _RAM_SLOTS)})
        state["modes"] = np.array(self.modes(), dtype=np.int64).reshape(-1, 2)
        return state

    def set_state(self, state: dict) -> None:
        """Restore a state from :meth:`get_state`; the piece is rebuilt deterministically."""
        s = [float(state[k]) for k in _STATE_KEYS]
        time, t0, u1, v1, u2, v2, w_in, w_outer, w_inner, q, kick, horizon = s
        self._modes = [(int(s1), int(s2))
                       for s1, s2 in np.asarray(state["modes"]).reshape(-1, 2)]
        st = self._st
        if self.has_ram:                # the ram's origin values, read by the piece's start
            for k, i in zip(_RAM_KEYS, _RAM_SLOTS):
                st[i] = float(state[k])
            st[STEPPING], st[EXT_T] = 0.0, time
        st[W_FACE] = float(state["W_face"])    # read by nothing the piece's start writes
        st[LOGGED] = 0.0               # the log continues from the restored modes
        st[MODE] = stepping.mode_code(*self._modes[-1]) if self._modes else -1.0
        self._start(st, self._par, self._log, t0, u1, v1, u2, v2, w_in, w_outer, w_inner, q,
                    int(kick), horizon)
        self.time = time


def compiled_model(values, growth: bool) -> RigidExact | None:
    """The compiled model of the parameter ``values`` (a mapping of contract names to floats;
    model II when ``growth``), checked and turned into the solver's constants in one compiled
    call; None where this does not build it: numba unavailable, a name or value the general
    path must convert or refuse, a ram or Smith damping (``build_model`` then takes the general
    path, which refuses with the table's message what the compiled check refused).

    The single-case API's build (:func:`pipeplug.build_model`): each step here costs a
    fraction of a microsecond, set by its count of Python operations, so there are few (the
    path's entry points are the class's, :func:`_common_path`; no method call).
    """
    common = _COMMON or _common_path()
    if not common:
        return None
    held = values_record(values)
    if held is None:
        return None
    flat, record = held
    record_into_compiled, rules, limits = common
    par = np.empty(N_PAR)
    if record_into_compiled(par, flat, record, rules, limits, growth) != BUILT:
        return None
    model = object.__new__(RigidExact)
    model._par, model._st, model._log = par, _FRESH.copy(), np.zeros(_LOG_SIZE)
    model._constant = (values.get("L2", _L2_DEFAULT), 0.0, 0.0)   # a float, as checked
    model._modes = []
    return model
