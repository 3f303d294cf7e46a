"""Regularised friction with a compiled right-hand side: the compiled competitors of the study.

The model is :mod:`pipeplug_harness.cost.regularised`'s (tanh(v/eps) friction, two segments
split at t0, analytic Jacobian, outputs at the sample times); here its right-hand side and
Jacobian are compiled, and the integrators are the ones a user can install:

- ``odeint-numba``: scipy's :func:`~scipy.integrate.odeint` (ODEPACK's LSODA) calling a
  numba-compiled right-hand side and Jacobian (each call still crosses into Python: scipy's
  integrators take no compiled callback);
- ``CVODE-numba``: SUNDIALS' CVODE (BDF, dense Newton) through scikit-sundae, calling a
  numba-compiled right-hand side and Jacobian;
- ``numbalsoda``: LSODA in C++ calling the right-hand side as a numba C callback (no Python
  inside the integration);
- ``diffrax-Kvaerno5``: diffrax's implicit Kvaerno5 with a PID step-size controller, the whole
  solve compiled by ``jax.jit`` (float64);
- ``fd-compiled``: the paper's explicit scheme (:mod:`pipeplug.rigid.fd`) as one numba loop over
  the samples and internal steps, calling the core's own contact projections, so that it gives
  the core's fd numbers (the study reports the largest difference).

Each family is optional (the ``compiled`` extra): :func:`available` names every one that cannot
run here and why. One-time costs (numba compiling, ``jax.jit`` tracing and compiling) are
measured apart by :func:`prepare` and never enter a run's time.
"""
from __future__ import annotations

import importlib
import math
import time

import numpy as np

from .cases import BenchCase
from .regularised import MAX_CALLS

#: family -> the modules it needs (besides numba)
FAMILIES = {"odeint-numba": ("numba", "scipy"), "CVODE-numba": ("numba", "sksundae"),
            "numbalsoda": ("numba", "numbalsoda"), "diffrax-Kvaerno5": ("jax", "diffrax"),
            "fd-compiled": ("numba",)}
#: how to get each family's modules
INSTALL = {"odeint-numba": "pip install 'pipeplug[compiled]'",
           "CVODE-numba": "pip install 'pipeplug[compiled]' (scikit-sundae)",
           "numbalsoda": "pip install numbalsoda (no wheel: builds from source with CMake, a C++ "
                         "and a Fortran compiler)",
           "diffrax-Kvaerno5": "pip install 'pipeplug[compiled]' (jax, diffrax)",
           "fd-compiled": "pip install 'pipeplug[fast]' (numba)"}
#: the families whose settings are fd steps (the others: eps and tolerances)
STEPPED = ("fd-compiled",)
#: samples of a segment solved by diffrax are padded to this many (one compiled solve serves
#: every segment of the study's grid)
_PAD = 2000
#: diffrax's step limit per segment (each step of Kvaerno5 is several stages and Newton
#: iterations: about MAX_CALLS evaluations of the right-hand side)
MAX_STEPS = MAX_CALLS // 8


def available(families) -> dict:
    """{family: why it cannot run} for the `families` whose modules do not import here."""
    why = {}
    for family in families:
        for module in FAMILIES[family]:
            try:
                importlib.import_module(module)
            except Exception as err:      # absent, or broken on this machine
                why[family] = (f"{module} does not import ({type(err).__name__}: {err}); "
                               f"{INSTALL[family]}")
                break
    return why


def _constants(bench: BenchCase, eps: float) -> np.ndarray:
    """(q, M1, M2, F2, eps, k1, L1, growth, calls): the right-hand side's data, q set per
    segment, and the count of its evaluations so far."""
    c = bench.case
    return np.array([0.0, c.M1, c.M2, c.F2, eps, c.P1 * c.tau1, c.L1, float(bench.growth),
                     0.0])


_KERNELS: dict = {}


def _numba_kernels():
    """The compiled right-hand side and Jacobian (compiled at the first call of each
    signature; :func:`prepare` makes those calls)."""
    if _KERNELS:
        return _KERNELS
    import numba

    @numba.njit(cache=False)
    def rhs_into(y, data, out):
        data[8] += 1.0
        if data[8] > MAX_CALLS:           # over budget: derivatives no integrator accepts
            out[:] = math.nan
            return
        q, m1, m2, f2, eps, k1, l1, growth = (data[0], data[1], data[2], data[3], data[4],
                                              data[5], data[6], data[7])
        u1, v1, v2 = y[0], y[1], y[3]
        limit = k1 * min(max(u1, 0.0), l1) if growth != 0.0 else k1 * l1
        f1 = limit * math.tanh(v1 / eps)
        fr = f2 * math.tanh((v1 - v2) / eps)
        out[0], out[1], out[2], out[3] = v1, (q - f1 - fr) / m1, v2, fr / m2

    @numba.njit(cache=False)
    def jac_into(y, data, jac):
        m1, m2, f2, eps, k1, l1, growth = (data[1], data[2], data[3], data[4], data[5], data[6],
                                           data[7])
        u1, v1, v2 = y[0], y[1], y[3]
        if growth != 0.0:
            limit, slope = k1 * min(max(u1, 0.0), l1), (k1 if 0.0 < u1 < l1 else 0.0)
        else:
            limit, slope = k1 * l1, 0.0
        th1, th2 = math.tanh(v1 / eps), math.tanh((v1 - v2) / eps)
        g1 = limit * (1.0 - th1 * th1) / eps
        g2 = f2 * (1.0 - th2 * th2) / eps
        jac[:, :] = 0.0
        jac[0, 1] = jac[2, 3] = 1.0
        jac[1, 0], jac[1, 1], jac[1, 3] = -slope * th1 / m1, -(g1 + g2) / m1, g2 / m1
        jac[3, 1], jac[3, 3] = g2 / m2, -g2 / m2

    @numba.njit(cache=False)
    def rhs(t, y, data):
        out = np.empty(4)
        rhs_into(y, data, out)
        if data[8] > MAX_CALLS:           # odeint would go on through every sample time
            raise RuntimeError("over the budget of right-hand-side evaluations")
        return out

    @numba.njit(cache=False)
    def jac(t, y, data):
        out = np.empty((4, 4))
        jac_into(y, data, out)
        return out

    @numba.njit(cache=False)
    def cvode_rhs(t, y, yp, user):
        rhs_into(y, user[0], yp)

    @numba.njit(cache=False)
    def cvode_jac(t, y, yp, jj, user):
        jac_into(y, user[0], jj)

    _KERNELS.update(rhs_into=rhs_into, jac_into=jac_into, rhs=rhs, jac=jac,
                    cvode_rhs=cvode_rhs, cvode_jac=cvode_jac)
    return _KERNELS


def _segments(bench: BenchCase):
    """(start, load, sample mask) of the two segments: the pulse, then no load."""
    times, t0 = bench.times, bench.case.t0
    return ((0.0, bench.case.Q0, times <= t0), (t0, 0.0, times > t0))


def _run_segments(bench: BenchCase, eps: float, segment) -> dict:
    """Both segments by ``segment(data, y0, start, times)`` (states 4 x n, or None on failure);
    a run whose right-hand side was called more than :data:`MAX_CALLS` times failed (as the
    interpreted runs do)."""
    data, y, columns = _constants(bench, eps), np.zeros(4), []
    for start, q, mask in _segments(bench):
        data[0] = q
        values = segment(data, y, start, bench.times[mask])
        if values is None:
            break
        columns.append(values)
        y = np.ascontiguousarray(values[:, -1])
    success = len(columns) == 2 and data[8] <= MAX_CALLS
    values = (np.concatenate(columns, axis=1) if success
              else np.full((4, len(bench.times)), np.nan))
    return {"U1": values[0], "V1": values[1], "U2": values[2], "V2": values[3],
            "success": success}


def run_odeint_numba(bench: BenchCase, eps: float, rtol: float, atol: float) -> dict:
    """scipy's odeint (LSODA) with the numba-compiled right-hand side and Jacobian."""
    from scipy.integrate import odeint
    k = _numba_kernels()

    def segment(data, y0, start, times):
        try:
            out, info = odeint(k["rhs"], y0, np.concatenate([[start], times]), args=(data,),
                               Dfun=k["jac"], tfirst=True, rtol=rtol, atol=atol,
                               mxstep=MAX_CALLS, full_output=True)
        except RuntimeError:
            return None
        return out[1:].T if info["message"] == "Integration successful." else None
    return _run_segments(bench, eps, segment)


def run_cvode_numba(bench: BenchCase, eps: float, rtol: float, atol: float) -> dict:
    """CVODE (BDF, dense Newton) with the numba-compiled right-hand side and Jacobian."""
    from sksundae.cvode import CVODE
    k = _numba_kernels()

    def segment(data, y0, start, times):
        solver = CVODE(k["cvode_rhs"], userdata=(data,), jacfn=k["cvode_jac"], method="BDF",
                       rtol=rtol, atol=atol, max_num_steps=MAX_CALLS)
        sol = solver.solve(np.concatenate([[start], times]), y0)
        return sol.y[1:].T if sol.success and len(sol.t) == len(times) + 1 else None
    return _run_segments(bench, eps, segment)


_LSODA: dict = {}


def _lsoda_rhs():
    """The right-hand side as a numba C callback ``(t, y, dy, data)`` for numbalsoda."""
    if not _LSODA:
        import numba
        from numbalsoda import lsoda_sig
        rhs_into = _numba_kernels()["rhs_into"]

        @numba.cfunc(lsoda_sig)
        def rhs(t, u, du, p):
            y = numba.carray(u, (4,))
            data = numba.carray(p, (9,))
            out = numba.carray(du, (4,))
            rhs_into(y, data, out)
        _LSODA["rhs"] = rhs.address
    return _LSODA["rhs"]


def run_numbalsoda(bench: BenchCase, eps: float, rtol: float, atol: float) -> dict:
    """numbalsoda's LSODA (C++) with the right-hand side as a numba C callback (it takes no
    Jacobian: LSODA builds it by differences)."""
    from numbalsoda import lsoda
    address = _lsoda_rhs()

    def segment(data, y0, start, times):
        values, ok = lsoda(address, y0, np.concatenate([[start], times]), data=data, rtol=rtol,
                           atol=atol, mxstep=MAX_CALLS)
        return values[1:].T if ok else None
    return _run_segments(bench, eps, segment)


_DIFFRAX: dict = {}


def _diffrax_solve():
    """The jitted diffrax solve of one segment: (data, y0, start, padded times, n, rtol, atol)
    -> (states n x 4 at the padded times, success)."""
    if _DIFFRAX:
        return _DIFFRAX["solve"]
    import jax
    jax.config.update("jax_enable_x64", True)
    import diffrax
    import jax.numpy as jnp

    def field(t, y, data):
        q, m1, m2, f2, eps, k1, l1, growth = (data[i] for i in range(8))   # no call count
        u1, v1, _, v2 = y[0], y[1], y[2], y[3]
        limit = jnp.where(growth != 0.0, k1 * jnp.clip(u1, 0.0, l1), k1 * l1)
        f1 = limit * jnp.tanh(v1 / eps)
        fr = f2 * jnp.tanh((v1 - v2) / eps)
        return jnp.stack([v1, (q - f1 - fr) / m1, v2, fr / m2])

    @jax.jit
    def solve(data, y0, start, times, rtol, atol):
        sol = diffrax.diffeqsolve(
            diffrax.ODETerm(field), diffrax.Kvaerno5(), t0=start, t1=times[-1], dt0=None,
            y0=y0, args=data, saveat=diffrax.SaveAt(ts=times),
            stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
            max_steps=MAX_STEPS, throw=False)
        return sol.ys, sol.result == diffrax.RESULTS.successful

    _DIFFRAX["solve"] = solve
    return solve


def run_diffrax(bench: BenchCase, eps: float, rtol: float, atol: float) -> dict:
    """diffrax's Kvaerno5 (implicit, PID step control) under ``jax.jit``; the segment's sample
    times are padded to a fixed length with its last time (one compiled solve for all)."""
    solve = _diffrax_solve()

    def segment(data, y0, start, times):
        padded = np.full(_PAD, times[-1])
        padded[:len(times)] = times
        ys, ok = solve(data, y0, start, padded, rtol, atol)
        return np.asarray(ys)[:len(times)].T if bool(ok) else None
    return _run_segments(bench, eps, segment)


_FD: dict = {}


def _fd_kernel():
    """The paper's scheme over the sample times, compiled: the steps of
    :class:`pipeplug.rigid.fd.RigidFd` (the same operations in the same order), driven as the
    study drives the core's fd model (one communication step per sample interval)."""
    if _FD:
        return _FD["run"]
    from pipeplug import jit
    jit.enabled()                         # registers the core's helpers with numba
    import numba

    from pipeplug.contact.coulomb import SLACK, one_contact, two_contacts
    from pipeplug.contact.outer import limit
    from pipeplug.rigid.fd import _ROUND_OFF as ROUND_OFF  # the scheme's own constant

    @numba.njit(cache=False)
    def run(m1, m2, f2, law, coupled, dt_max, loads, times, out):
        u1 = v1 = u2 = v2 = p_max = f1 = fr = previous = 0.0
        for j in range(times.shape[0]):
            q, h = loads[j], times[j] - previous
            if not (q == 0.0 and v1 == 0.0 and v2 == 0.0 and f1 == 0.0 and fr == 0.0):
                n = max(1, math.ceil(h / dt_max - 1e-9))
                tau = h / n
                for _ in range(n):
                    c1 = tau * limit(law, u1)
                    if coupled:
                        w1, w2, p1, p2, _, _ = two_contacts(
                            m1, m2, v1 + tau * q / m1, v2, c1, tau * f2, ROUND_OFF * p_max)
                    else:
                        trial = v1 + tau * q / m1
                        w1, p1 = one_contact(m1, trial, c1, max(
                            SLACK * (abs(m1 * trial) + c1), ROUND_OFF * p_max))
                        w2, p2 = 0.0, 0.0
                    p_max = max(p_max, m1 * abs(w1) + m2 * abs(w2))
                    u1 += tau * w1
                    u2 += tau * w2
                    v1, v2, f1, fr = w1, w2, p1 / tau, p2 / tau
            previous = times[j]
            out[0, j], out[1, j], out[2, j], out[3, j] = v1, v2, u1, u2

    _FD["run"] = run
    return run


def run_fd_compiled(bench: BenchCase, dt: float) -> dict:
    """The paper's scheme, compiled, with internal steps <= `dt` [s] in each sample interval."""
    import pipeplug
    from pipeplug.contact.outer import outer_contact_for
    run = _fd_kernel()
    p = pipeplug.Params.from_mapping(dict(bench.params, dt=dt)).validate(frozenset({"fd"}))
    law = tuple(float(x) for x in outer_contact_for(p.P1, p.L1, p.tau1, bench.growth))
    out = np.empty((4, len(bench.times)))
    run(p.M1, p.M2, p.F2, law, p.has_plug, p.dt, bench.loads, bench.times, out)
    return {"V1": out[0], "V2": out[1], "U1": out[2], "U2": out[3]}


RUNS = {"odeint-numba": run_odeint_numba, "CVODE-numba": run_cvode_numba,
        "numbalsoda": run_numbalsoda, "diffrax-Kvaerno5": run_diffrax}


def prepare(family: str, bench: BenchCase) -> float:
    """Run ``family`` once untimed on `bench` (compiling the right-hand side or the fd loop,
    tracing and compiling a jitted solve); returns that first call's wall time [s]."""
    start = time.perf_counter()
    if family in STEPPED:
        run_fd_compiled(bench, 2e-4)
    else:
        RUNS[family](bench, 1e-3, 1e-6, 1e-9)
    return time.perf_counter() - start
