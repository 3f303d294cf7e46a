"""The struck end of the elastic pipe when a ram strikes it: the ram and its cushion.

The ram is a rigid mass ``m`` [kg] moving along the pipe's axis; between it and the pipe's head
is a cushion, a spring that pushes but never pulls, loaded along ``k`` [N/m] and unloaded along
the stiffer ``k / e^2`` (Smith's convention; ``e`` the coefficient of restitution), reloading
along the unloading line up to the largest compression reached::

    F(delta) = max(0, min(k delta, k delta_max - (k / e^2) (delta_max - delta)))

``delta`` [m] is the cushion's compression (the ram's displacement minus the head's). A direct
strike, steel on steel, has the head's own contact stiffness: ``k = e^2 E1 S1 / dx``, so that
its unloading stiffness is that of one cell of the pipe (the direct strike's exact limit is
reached as dx -> 0; its reference F(t) = Z v0 exp(-Z t / m) is for a rigid ram on a long rod).

On the staggered grid the ram is one more node ahead of the pipe's first cell and the cushion
one more face: each internal step the ram takes the kick ``-F h / m``, the head face carries
``-(Q + F)``, and after the pipe's cells have moved the compression drifts with the relative
velocity ``delta += h (v_ram - v_head)`` and the force follows the law above. The ram is stable
with the pipe when ``h^2`` times the largest stiffness per mass at the head stays within the
leapfrog's limit (:func:`stable_cushion`, checked when the model is built).

Energy: the cushion holds the recoverable energy of its unloading line, in the scheme's form
``R = F (F - (k / e^2) h (v_ram - v_head)) / (2 k / e^2)``; the work done on it (the force times
the step's mean compression rate) less ``R`` is its loss, ``W_cushion``: 0 along the unloading
line, ``(1 - e^2)`` of the work on the loading line. With the ram's kinetic energy in
``E_kinetic`` and ``R`` in ``E_strain``, ``W_input + W_ram = E_kinetic + E_strain + W_friction +
W_cushion`` (a strike resets the cushion, below). Where the
cushion opens within a step (its force would turn to a pull), cutting the force to 0 would let
the scheme take back up to ``k h^2 dv^2 / 2`` (dv the closing velocity), energy created at
every separation. Instead the unloading line goes on for one more step, a pull of at most
``(k / e^2) h |dv|`` (``m_cell |dv| / h`` for a direct strike, an impulse of first order in
dx), and the force is cut to 0 a step later: there the loss grows by ``F F' / (2 k / e^2) >= 0``
(both forces pulls), so ``W_cushion`` never decreases at a separation.

Over any step the loss grows by ``(F + F') (U' - F') / (2 k / e^2)``: ``F`` the step's force,
``F'`` the next step's and ``U' = F + (k / e^2) h (v_ram - v_head)`` the unloading line's (the
step's work less the change of ``R``, whatever the law). It is >= 0 where ``F'`` lies between
``-F`` and ``U'``, which the law gives while ``F >= 0`` (``0 <= F' <= U'``) but for the
separation above. In the step after a pull (``F < 0``) the cushion may close again (a head
bouncing back at the ram); the law's push may then be below ``-F``, and the loss would fall.
That step's force is held between ``-F`` and ``U'`` (at most the unloading line's push), of
the order of the pull before it and off the law. While a head chatters at the ram (the cushion
opening and closing within steps, push and pull by turns) such forces can follow each other
for several steps, on or near the unloading line, where the cushion loses nothing: at the
scale of a step, rare with a ram of several cells (2 of 120,000 communication points in 300
random scenes with loads pulling the head back).

A strike resets the cushion (:func:`start_strike`) and replaces the ram's kinetic energy
(``W_ram`` gains the new ``m v^2 / 2`` less the old). What the cushion still held, ``R``, is
lost with it where ``R >= 0``: ``W_cushion`` rises by ``R``. ``R`` is the scheme's form, not a
spring's energy, and is negative where the closing velocity's term exceeds the force: in the
step of pull after a separation ``R = F F' / (2 k / e^2) < 0`` (``F > 0`` the last push, ``F'
< 0`` the pull; at most ``(k / e^2) h^2 dv^2 / 8`` in size, ``m_cell dv^2 / 8`` for a direct
strike (Courant <= 1), ``dv`` the closing velocity then, which loads and waves, not the strike,
set), and in a push that closes fast (the first step of a strike, a push held off the law
above). There ram and head hold that much more kinetic energy than the scheme's energy (the
push acted over the whole step), which the next steps would take back. The strike cancels
them and the bodies keep it; no loss can be negative, so it counts as energy the strike
brought: ``W_ram`` gains ``-R`` too and ``W_cushion`` does not change (the work on the cushion
takes ``-R``). So ``W_cushion`` never decreases, at strikes included, but for round-off: it is
the work on the cushion (a compensated sum) less ``R`` computed from the state when it is
output, and the two round apart, so between two outputs it may fall by a few units of the
last place of the largest work (measured: 8e-17 of it; allowed in the tests: 16 eps).
"""
from __future__ import annotations

from ..jit import jitable
from .cells import accumulate

__all__ = ["cushion_force", "ram_step", "start_strike", "stable_cushion", "cushion_energy"]


@jitable
def cushion_force(delta, delta_max, k, k_unload):
    """The cushion's force [N] at compression ``delta`` [m] after the largest ``delta_max``."""
    return max(0.0, min(k * delta, k * delta_max - k_unload * (delta_max - delta)))


@jitable
def ram_step(q, dt, v_head_old, v_head, mass, k, k_unload, ram, acc, work_index, compensation):
    """One internal step of ram and cushion after the pipe's (``v_head_old`` -> ``v_head``
    [m/s], the first cell's velocity, moved by the head force ``-(q + F)``).

    ``ram`` holds [velocity m/s, compression m, largest compression m, force N of the step
    ahead, transferred work J, its rounding error]; ``acc[work_index]`` the work done on the
    cushion [J] (compensated sum, its error at ``compensation``). Returns the head force of the
    next step, ``q + F`` [N].
    """
    force = ram[3]
    v_old = ram[0]
    v_new = v_old - dt * force / mass
    ram[0] = v_new
    accumulate(acc, work_index, compensation,
               0.5 * dt * force * ((v_old - v_head_old) + (v_new - v_head)))
    accumulate(ram, 4, 5, 0.5 * dt * (q + force) * (v_head_old + v_head))
    delta = ram[1] + dt * (v_new - v_head)
    ram[1] = delta
    ram[2] = max(ram[2], delta)
    law = cushion_force(delta, ram[2], k, k_unload)
    # The loss grows over the step by (F + F') (U' - F') / (2 k_unload): F this step's force,
    # F' the next, U' = F + k_unload dt (v_new - v_head) the unloading line's (module
    # docstring), so F' must lie between -F and U'. The law's F' does while F >= 0 but where
    # the cushion opens within the step.
    line = force + k_unload * dt * (v_new - v_head)
    if law == 0.0 and force > 0.0:
        # The cushion opened within this step: its force acted over the whole step, and
        # cutting it to 0 now would give back up to k_unload dt^2 dv^2 / 2. Continuing the
        # unloading line for one more step (a pull of at most k_unload dt |dv|) keeps the
        # ledger exact here, and the next step's cut then dissipates instead.
        law = line
    elif force < 0.0:
        # The step after such a pull. Still open (U' <= 0), the cut to 0 dissipates F U'.
        # Closed again within it (a head bouncing back at the ram), the law's push can fall
        # below -F, and the loss would fall (by 6.5 J of 13,400 J in fuzz case 202:46): the
        # push is held between -F and U' for this step, at most the unloading line's.
        law = min(max(law, min(-force, line)), max(-force, line))
    ram[3] = law
    return q + law


@jitable
def start_strike(ram, velocity):
    """Put the ram at the head, touching an unloaded cushion, with ``velocity`` [m/s]."""
    ram[0] = velocity
    ram[1] = 0.0
    ram[2] = 0.0
    ram[3] = 0.0


def cushion_energy(force, v_ram, v_head, k_unload, dt):
    """The recoverable energy of the cushion [J] in the scheme's form (module docstring)."""
    if force == 0.0:
        return 0.0
    return force * (force - k_unload * dt * (v_ram - v_head)) / (2.0 * k_unload)


def stable_cushion(k_unload, ram_mass, cell_mass, cell_stiffness, dt) -> float:
    """The largest unloading stiffness [N/m] the leapfrog step ``dt`` [s] takes at the head:
    Gershgorin's bound of the stiffness per mass of the ram's row and of the first cell's row
    (``cell_stiffness = E1 S1 / dx`` [N/m]) within ``4 / dt^2``."""
    limit = 4.0 / (dt * dt)
    from_ram = 0.5 * limit * ram_mass
    from_cell = 0.5 * limit * cell_mass - cell_stiffness
    return min(from_ram, from_cell)
