"""Many single blows at once: the exact rigid solver over arrays of parameters.

A case is a parameter set plus one rectangular blow from rest (``amplitude`` [N] for
``duration`` [s], then no load), advanced until all is at rest. The whole batch runs in one call
of one compiled loop (numba, when available; plain Python otherwise), model build included: the
parameters are checked and turned into solver constants as arrays, and each case starts from a
fresh state::

    from pipeplug.batch import blows
    out = blows({"tau1": np.linspace(0.0, 6e4, 1000)}, amplitude=23e3, duration=0.05)
    out["u_pipe"]            # final pipe displacement of each case [m]

The values are those of :func:`pipeplug.build_model` advanced through the same blow and then
under no load in steps doubling from the blow's duration, the last one cut at ``t_max``, until
all is at rest (the same functions, :mod:`pipeplug.rigid.stepping`, and the same steps).
"""
from __future__ import annotations

import math

import numpy as np

from . import jit
from .params import ParamArrays, ParameterError
from .rigid.record import (
    T0,
    TIME,
    U1,
    U2,
    W_FACE,
    W_IN,
    W_INNER,
    W_OUTER,
    as_array,
    parameter_record,
    reset_state,
    state_record,
)
from .rigid.stepping import (
    MAX_EVENTS_PER_STEP,
    OK,
    SEGMENT_MISSED,
    TOO_MANY_EVENTS,
    at_rest,
    step_to,
)

__all__ = ["blows", "RESULTS"]

#: the results of each case, in the order of the kernel's table
RESULTS = ("u_pipe", "u_plug", "W_input", "W_friction_outer", "W_friction_inner", "W_face",
           "t_rest", "t_end")


def blows(params=None, amplitude=23e3, duration=0.05, contact_growth: bool = False, *,
          t_max: float = 100.0, compiled: bool = True) -> dict:
    """Run one rectangular blow from rest on each parameter set, until all is at rest.

    Parameters
    ----------
    params : mapping of str to float or array, optional
        Parameter values by contract name (SI), broadcast to one length; missing ones take
        their defaults. Only the rigid models' parameters matter.
    amplitude : float or array
        Struck-end force during the blow [N].
    duration : float or array
        Length of the blow [s], > 0.
    contact_growth : bool
        Model II (outer friction over the penetrated length) instead of model I.
    t_max : float
        A case not at rest by this time [s] (e.g. tau1 = 0: nothing stops the pipe) has
        ``t_rest = inf`` and NaN for its other results (``t_end = t_max``); the steps stop
        there.
    compiled : bool
        Run compiled when numba is available (default), else plain Python.

    Returns
    -------
    dict of arrays
        Per case: ``u_pipe``, ``u_plug`` [m] at rest, ``W_input``, ``W_friction_outer``,
        ``W_friction_inner``, ``W_face`` [J] (the work against the end resistance, 0 without
        one; all of the input work is dissipated), ``t_rest`` [s], the
        time from the blow's start at which all is at rest, and ``t_end`` [s], the end of the
        step after which it was found at rest: the blow, then steps doubling from its duration
        (``duration``, ``2 duration``, ``4 duration``, ...; the last one cut at ``t_max``).

    Raises
    ------
    ParameterError
        Naming the first offending parameter (or ``amplitude``, ``duration``) and its value.
    """
    columns = ParamArrays(params or {}).validate()
    amplitude, duration = _loads(amplitude, duration, columns.size)
    pars = np.column_stack(np.broadcast_arrays(*parameter_record(columns, contact_growth)))
    out = np.empty((len(pars), len(RESULTS)))
    par, st, log = [0.0] * pars.shape[1], state_record(), []      # no mode log kept
    kernel = jit.compiled(blows_into) if compiled else blows_into
    if kernel is not blows_into:
        par, st, log = as_array(par), as_array(st), np.zeros(0)
    code, case = kernel(st, par, log, pars, amplitude, duration, float(t_max), out)
    if code != OK:
        why = {TOO_MANY_EVENTS: f"more than {MAX_EVENTS_PER_STEP} friction events in one step",
               SEGMENT_MISSED: "a segment event found off its segment end"}.get(code, code)
        raise RuntimeError(f"case {case}: the exact solver failed: {why}")
    return dict(zip(RESULTS, out.T.copy()))


def _loads(amplitude, duration, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Amplitudes [N] and durations [s] as arrays of ``n`` cases, checked."""
    amplitude = np.broadcast_to(np.asarray(amplitude, dtype=float), (n,)).copy()
    duration = np.broadcast_to(np.asarray(duration, dtype=float), (n,)).copy()
    if not np.all(np.isfinite(amplitude)):
        raise ParameterError("amplitude", float(amplitude[~np.isfinite(amplitude)][0]),
                             "finite [N]")
    if not np.all((duration > 0.0) & np.isfinite(duration)):
        bad = ~((duration > 0.0) & np.isfinite(duration))
        raise ParameterError("duration", float(duration[bad][0]), "finite, > 0 [s]")
    return amplitude, duration


@jit.jitable
def blows_into(st, par, log, pars, amplitude, duration, t_max, out):
    """For each case ``i``: the constants ``pars[i]`` (a parameter record), a blow of
    ``amplitude[i]`` [N] for ``duration[i]`` [s] from rest, then no load until all is at rest;
    writes :data:`RESULTS` into ``out[i]``. ``st`` and ``par`` are work records, ``log`` an
    empty mode log (none kept).

    Returns ``(code, case)``: :data:`~pipeplug.rigid.stepping.OK`, or the failure and its case.
    """
    for i in range(pars.shape[0]):
        for j in range(pars.shape[1]):
            par[j] = float(pars[i, j])
        reset_state(st)
        h = float(duration[i])
        code = step_to(st, par, log, float(amplitude[i]), h)
        while code == OK and not at_rest(st) and st[TIME] < t_max:
            code = step_to(st, par, log, 0.0, min(t_max, st[TIME] + h))    # doubling steps
            h = 2.0 * h
        if code != OK:
            return code, i
        if at_rest(st):
            out[i, 0], out[i, 1] = st[U1], st[U2]
            out[i, 2], out[i, 3], out[i, 4] = st[W_IN], st[W_OUTER], st[W_INNER]
            out[i, 5] = st[W_FACE]            # at rest: the piece adds none
            out[i, 6] = st[T0]
        else:
            for j in range(6):
                out[i, j] = math.nan
            out[i, 6] = math.inf
        out[i, 7] = st[TIME]
    return OK, -1
