"""Cutting a model III plug at a cell face (a clean-out): the state the kept plug goes on with.

The scheme's energy of a rod (:mod:`pipeplug.elastic.model`) is
``E = K(v) + sum Nbar^2 / (2 k)`` with the kinetic part ``K(v) = v^T M v / 2``, the scheme's
inertia ``M = diag(m) - (h^2 / 4) A`` (``A`` the rod's stiffness matrix: k on the diagonal per
inner face a cell touches, -k beside it) and ``Nbar`` the face forces at the step's time.
``M v`` is the scheme's momentum: cell by cell ``m (v_prev + 2 v + v_next) / 4``, the momentum
averaged over the two steps either side of the instant (without friction), and its sum is the
rod's momentum ``sum m v`` (the rows of ``A`` sum to 0).

A cut at face c takes that face's spring out of ``A``: each side's inertia grows by the
rank-one term ``beta e e^T`` (``beta = k h^2 / 4``, ``e`` the difference across the face). Kept
at their velocities, the two sides would hold ``beta (v_c - v_{c-1})^2 / 2`` more kinetic
energy than the whole did: where the plug oscillates cell to cell (at Courant 1 the scheme's
energy gives that pattern almost none) a clean-out created energy (fuzz seed 2031, case 148:
W_removed = -0.012 J). What the cut does instead is what a sudden change of inertia does: each
cell keeps its scheme momentum, ``v' = M_after^-1 M_before v``, at unchanged forces ``Nbar``
(strains). Then ``K' = p^T M_after^-1 p / 2 <= p^T M_before^-1 p / 2 = K`` (``M_after >=
M_before``), as soil joining the plug at constant momentum loses energy; with the cut spring's
strain ``Nbar_c^2 / (2 k) >= 0`` gone too, the removed soil takes ``W_removed = E_before -
E_kept >= E_removed >= 0``, its own kinetic and strain energy at least. Only the kept side's
velocities are needed: ``v'_K = v_K - beta (v_c - v_{c-1}) M_K^-1 e_c`` (``M_K`` the kept rod's
inertia, ``e_c`` its first cell), so the kept plug's momentum changes by ``-beta (v_c -
v_{c-1}) = -h (N_c - N_c^-) / 4``, a quarter of the change of the cut face's impulse over a
step, and the removed soil's by the opposite. A plug moving as one (no velocity jump at the
cut) keeps its velocities exactly.
"""
from __future__ import annotations

import numpy as np

__all__ = ["cut_rear"]


def cut_rear(v: np.ndarray, N: np.ndarray, m: np.ndarray, k: float, h: float,
             keep: int) -> None:
    """Cut a plug behind its last ``keep`` cells, in place (module docstring).

    Parameters
    ----------
    v : ndarray
        The plug's cell velocities [m/s], rear first (``d`` cells, ``1 <= keep < d``).
    N : ndarray
        Its face forces of the half step ahead [N] (``d + 1``, the end faces 0).
    m : ndarray
        Its cells' masses [kg] (``d``).
    k : float
        A cell's stiffness ``E2 S2 / dx`` [N/m].
    h : float
        The internal step [s].
    keep : int
        Cells kept at the front; the cells behind them and their faces are zeroed, the cut
        face too (the kept plug's free end).
    """
    c = v.size - keep
    kept, Nk = v[c:], N[c:]
    beta = 0.25 * k * h * h
    jump = kept[0] - v[c - 1]
    # the forces at the step's time (strains) stay: each inner face's force of the half step
    # ahead moves with the velocity difference across it, N = Nbar + (k h / 2) D v
    old_difference = np.diff(kept)
    diagonal = m[c:] - 2.0 * beta
    diagonal[0] += beta
    diagonal[-1] += beta
    rhs = np.zeros(keep)
    rhs[0] = beta * jump
    kept -= _tridiagonal(diagonal, beta, rhs)
    Nk[1:-1] += 0.5 * k * h * (np.diff(kept) - old_difference)
    v[:c] = 0.0
    N[:c + 1] = 0.0


def _tridiagonal(diagonal: np.ndarray, off: float, rhs: np.ndarray) -> np.ndarray:
    """Solve the symmetric tridiagonal system with ``diagonal`` and the constant ``off``
    beside it (the scheme's inertia: positive definite and diagonally dominant for Courant
    <= 1, so elimination without pivoting is stable)."""
    n = diagonal.size
    d = diagonal.astype(float).copy()
    r = rhs.astype(float).copy()
    for i in range(1, n):
        w = off / d[i - 1]
        d[i] -= w * off
        r[i] -= w * r[i - 1]
    x = np.empty(n)
    x[-1] = r[-1] / d[-1]
    for i in range(n - 2, -1, -1):
        x[i] = (r[i] - off * x[i + 1]) / d[i]
    return x
