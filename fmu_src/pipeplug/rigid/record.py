"""The records of the exact solver: its constants and its state, each a flat row of floats.

The exact solver's functions (:mod:`~pipeplug.rigid.pieces`, :mod:`~pipeplug.rigid.stepping`)
read and write two records by the indices below: numba compiles them for float64 arrays, and
Python runs the same source on lists (which Python indexes faster than arrays).

Constants (``par``): masses, the plug's friction limit and the outer friction law
(:mod:`pipeplug.contact.outer`). State (``st``): the model's time, the current piece (its origin,
contact modes, closed-form motion and forces), the works done before it, and its next event.
"""
from __future__ import annotations

import math

import numpy as np

from ..contact.outer import outer_contact_for
from ..jit import jitable
from ..params import (
    DERIVED,
    face_limit,
    first_refused,
    has_damping,
    has_plug,
    has_ram,
    inner_limit,
    limit_values,
    outer_perimeter,
    pipe_mass,
    plug_face_limit,
    plug_mass,
    wall_section,
)

__all__ = ["parameter_record", "record_into", "state_record", "reset_state", "as_array", "N_PAR",
           "N_STATE", "BUILT", "ELSEWHERE"]

# The parameters' formulas and checks (pipeplug.params: the one table) run compiled here too.
for _helper in (*DERIVED.values(), first_refused, limit_values):
    jitable(_helper)
#: what record_into returns besides a refused value's index: the record is written; the values
#: are valid but call for a variant it does not build (a ram, Smith damping)
BUILT, ELSEWHERE = -1, -2

# Constants: pipe mass M1 [kg]; plug mass M2 [kg] and its friction limit F2 = P2 L2 tau2 [N]
# (both 0 without a plug); 1.0 when the plug is coupled; the outer law (kind, F1 [N],
# k [N/m], L1 [m]) in four places from P_LAW; the wall's section S1 [m2] and the coupled plug's
# length L2 [m] (0 without a plug), for the axial stress.
P_M1, P_M2, P_F2, P_COUPLED, P_LAW = range(5)
P_S1, P_L2 = P_LAW + 4, P_LAW + 5
# The ram (:mod:`pipeplug.rigid.ram`): its mass [kg] (0: no ram), the cushion's loading and
# unloading stiffness k and k / e^2 [N/m] (0: a direct strike) and e^2 [1]; e [1].
P_RAM_M, P_K, P_KU, P_E2, P_E = range(P_L2 + 1, P_L2 + 6)
# The end resistance (:mod:`pipeplug.rigid.face`): the pipe's Qf = q_face S1 [N], the coupled
# plug's Qp = q_plug_face S2 [N] (0 without a plug), and FACE 1.0 when either acts (0.0: the
# pieces are those of a model without it, bit for bit).
P_QF, P_QP, P_FACE = range(P_E + 1, P_E + 4)
N_PAR = P_FACE + 1

# State. TIME: the model's time [s]. The piece: its start T0 [s] and force Q [N] (nan before
# the first step), its origin U1, V1, U2, V2 [m, m/s], contact modes S1, S2 (-1, 0, 1) and KIND
# (pieces.AT_REST ...); the motions of pipe and plug (a body at rest, or absent, has a motion
# of zeros): acceleration A1, A2 [m/s^2], stiffness per mass K1, K2 [1/s^2] and W1, W2 =
# sqrt(|K|) [1/s]; the outer segment FORCE0 [N], KAPPA [N/m], END [m]; static forces FS1, FS2
# [N]. Works before the piece W_IN, W_OUTER, W_INNER [J]; KICK: the plug's breakaway direction
# at the piece start. The event search: HORIZON [s] after T0 searched, the event T_EVENT [s]
# and its LABELS (bits), T_SNAP [s] (a step ending past it takes the event), SEARCHED [s]
# (events known up to it). The mode log (see stepping.log_mode): MODE, the code of the last
# piece's contact modes logged (-1: none yet), and LOGGED, the codes in the log array not yet
# taken by the model. ERROR: a value for the message of a failure.
(TIME, T0, Q, U1, V1, U2, V2, S1, S2, KIND, A1, K1, W1, A2, K2, W2, FORCE0, KAPPA, END, FS1,
 FS2, W_IN, W_OUTER, W_INNER, KICK, HORIZON, T_EVENT, T_SNAP, SEARCHED, LABELS, MODE, LOGGED,
 ERROR) = range(33)
# The ram (only models with a ram use these; :mod:`pipeplug.rigid.ram`). At the piece's origin:
# RAM_ON (1.0 once struck), the cushion's compression D0 [m] (the ram's displacement less the
# head's since the strike), the ram's velocity VR [m/s], the largest compression DMAX [m], the
# strikes' energy W_RAM [J] and the cushion's loss W_CUSH [J] before the piece, VSCALE [m/s]
# (the fastest direct impact since the strike), KICK1 (the pipe's breakaway direction) and ZW
# [m/s] (the closing velocity of the direct impact the piece starts with; 0: none). The piece:
# RAM its kind (ram.NONE ...), the compression's motion DV, DA, DK, DW (as a motion of
# :mod:`~pipeplug.rigid.motion` from D0), RHO the pipe's share of it (0: the pipe does not feel
# it), DB [m] and KB [N/m] of the cushion's branch (F = KB (delta - DB)), FC0 [N] its force at
# the origin, ZT [s] the length of a Zeno piece. The communication step: its extremes of the
# axial force N_LOW, N_HIGH [N], taken up to EXT_T [s]; STEPPING 1.0 while a step is under way.
(RAM_ON, D0, VR, DMAX, W_RAM, W_CUSH, VSCALE, KICK1, ZW, RAM, DV, DA, DK, DW, RHO, DB, KB, FC0,
 ZT, N_LOW, N_HIGH, EXT_T, STEPPING) = range(ERROR + 1, ERROR + 24)
# The end resistance (all 0.0 without it): S3 the plug/soil mode (sign of the plug's velocity,
# 0 held), the work done against it before the piece W_FACE [J], and the soil's end forces in
# the piece, constant there, on the pipe's annulus FACE1 and on the plug's face FACE3 [N] (<= 0).
S3, W_FACE, FACE1, FACE3 = range(STEPPING + 1, STEPPING + 5)
N_STATE = FACE3 + 1


@jitable
def parameter_record(params, growth):
    """The constants of the exact solver (a list) for validated ``params`` (model II when
    ``growth``).

    ``params`` is a :class:`~pipeplug.params.Params`, a :class:`~pipeplug.params.ParamArrays`
    of many cases (then each entry is an array over the cases) or, compiled, a record of
    :data:`~pipeplug.params.RECORD_DTYPE`.
    """
    coupled = has_plug(params)
    law = outer_contact_for(outer_perimeter(params), params.L1, params.tau1, growth,
                            params.q_face)
    e = params.cushion_restitution
    k = params.cushion_stiffness
    qf, qp = face_limit(params), coupled * plug_face_limit(params)
    return [pipe_mass(params), coupled * plug_mass(params), coupled * inner_limit(params),
            coupled * 1.0, law[0], law[1], law[2], law[3], wall_section(params) + 0.0 * params.L1,
            coupled * params.L2, params.ram_mass, k, k / (e * e), e * e, e, qf, qp,
            1.0 * ((qf > 0.0) | (qp > 0.0))]


@jitable
def record_into(par, values, record, rules, limits, growth):
    """Check parameter values and write the exact solver's constants of model I (model II when
    ``growth``) into ``par``, at once (the single-case API's compiled build).

    ``values`` holds the values in the order of :data:`~pipeplug.params.PARAMETERS`, ``record``
    the same memory as a record array of :data:`~pipeplug.params.RECORD_DTYPE`; ``rules`` and
    ``limits`` are the table's checks (:func:`~pipeplug.params.check_rules`).

    Returns the index :func:`~pipeplug.params.first_refused` gives for a refused value,
    :data:`ELSEWHERE` for valid values that call for a ram or Smith damping (not built here),
    else :data:`BUILT`.
    """
    p = record[0]
    refused = first_refused(values, p, rules, limits)
    if refused >= 0:
        return refused
    if has_ram(p) or has_damping(p):
        return ELSEWHERE
    constants = parameter_record(p, growth)
    for i in range(N_PAR):
        par[i] = constants[i]
    return BUILT


def state_record() -> list:
    """A state at t = 0, before the first step: at rest, under no force yet (Q = nan)."""
    st = [0.0] * N_STATE
    reset_state(st)
    return st


@jitable
def reset_state(st):
    """Put the state record ``st`` back to that of a fresh model (see :func:`state_record`)."""
    for i in range(N_STATE):
        st[i] = 0.0                   # the piece: at rest at the origin, no force, no work
    st[Q] = math.nan
    st[MODE] = -1.0
    st[T_EVENT] = st[T_SNAP] = st[SEARCHED] = math.inf


def as_array(record) -> np.ndarray:
    """A record as the float64 array compiled functions take."""
    return np.array(record, dtype=np.float64)
