"""The axial stress along the pipe at instants of a short blow (elastic model III), from the FMI
3.0 FMU's profile array ``stress_pipe_profile``.

The scene: the package defaults with ``elastic = True`` and a blow Q0 = 23 kN held for
:data:`BLOW` = 0.1 ms, half the time a wave takes along the 1 m steel pipe (c1 = sqrt(E1/rho1)
= 5000 m/s). Left, without friction (tau1 = tau2 = 0): the compressive wave of -Q0/S1 enters at
the head, runs to the free far end and comes back as tension, drawn over d'Alembert's solution
of the free rod (:func:`free_rod_stress`, from the parameters alone). Right, with soil friction
tau1 = 2e4 Pa and the plug's tau2 = 1e4 Pa: the waves lose height as they run. The stresses
are node-centred (docs/elastic.md, root cause 8: the faces themselves alternate between two
levels under friction at Courant 1).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pipeplug import Params
from pipeplug.interface import profile_sections
from pipeplug_harness import io
from pipeplug_harness.session import FmuSession

__all__ = ["BLOW", "INSTANTS", "SCENES", "free_rod_stress", "stress_profiles",
           "draw_stress_profiles"]

Q_BLOW, BLOW = 23e3, 1e-4               # the blow [N] and how long it is held [s]
STEP = 1e-5                             # communication step [s]: 5 internal steps of dx/c1
INSTANTS = (5e-5, 1e-4, 1.5e-4, 2e-4, 2.5e-4, 3e-4)      # [s], before any second reflection
POINTS = 101
#: name -> (title, start values)
SCENES = {
    "frictionless": ("no friction (τ1 = τ2 = 0)", {"tau1": 0.0, "tau2": 0.0}),
    "friction": ("soil τ1 = 20 kPa, plug τ2 = 10 kPa", {"tau1": 2e4, "tau2": 1e4}),
}


def stress_profiles(fmu, params: dict) -> tuple[np.ndarray, dict]:
    """The sections [m] and the stress profile [Pa] at each of :data:`INSTANTS` [s], from a
    run of the FMI 3.0 FMU ``fmu`` under the blow, elastic, with ``params``."""
    marks = {round(t / STEP): t for t in INSTANTS}
    values = {"elastic": True, "dx": 0.01, "profile_points": POINTS, **params}
    out = {}
    with FmuSession(fmu, values, name="stress") as session:
        for k in range(max(marks)):
            t = k * STEP
            session.step(t, STEP, Q_BLOW if t < BLOW - 1e-12 else 0.0)
            if k + 1 in marks:
                out[marks[k + 1]] = session.profiles(["stress_pipe_profile"])[
                    "stress_pipe_profile"]
    p = Params()
    return profile_sections(p.L1, p.L2, POINTS)[0], out


def free_rod_stress(x, t: float, p: Params | None = None) -> np.ndarray:
    """d'Alembert's stress [Pa] in the free rod struck by the blow, before the wave returns to
    the head (t < 2 L1 / c1 + x / c1): the incident wave and its reflection at the free end,
    which changes its sign."""
    p = p or Params()
    c1 = (p.E1 / p.rho1) ** 0.5

    def wave(s):
        return np.where((s > 0.0) & (s < BLOW), -Q_BLOW / p.S1, 0.0)
    x = np.asarray(x, dtype=float)
    return wave(t - x / c1) - wave(t - (2 * p.L1 - x) / c1)


def draw_stress_profiles(path: Path, fmu, data: Path | None = None) -> Path:
    """The figure at ``path`` (and its profiles as CSV at ``data``: scene, t [s], x [m],
    stress [Pa]); returns the figure's path."""
    p = Params()
    fine = np.linspace(0.0, p.L1, 2001)
    f, axes = io.subplots(1, 2, figsize=(12, 5), sharey=True)
    records = []
    for ax, (name, (title, params)) in zip(axes, SCENES.items()):
        x, profiles = stress_profiles(fmu, params)
        records += [{"scene": name, "t": t, "x": xk, "stress": sk}
                    for t, stress in sorted(profiles.items()) for xk, sk in zip(x, stress)]
        for i, (t, stress) in enumerate(sorted(profiles.items())):
            ax.plot(x, stress / 1e6, ".-", color=f"C{i}", lw=1.2, ms=2.5,
                    label=f"t = {t * 1e3:.2f} ms")
            if name == "frictionless":
                ax.plot(fine, free_rod_stress(fine, t, p) / 1e6, "--", color="k", lw=0.7)
        ax.axhline(-Q_BLOW / p.S1 / 1e6, color="gray", ls=":", lw=0.8)
        ax.set(xlabel="x along the pipe [m] (0: struck head)", xlim=(0.0, p.L1))
        ax.set_title(title, fontsize=9)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("axial stress [MPa] (compression negative)")
    axes[0].plot([], [], "k--", lw=0.7, label="d'Alembert, free rod")
    axes[0].plot([], [], ":", color="gray", label="-Q0/S1")
    axes[0].legend(fontsize=8, loc="center left")
    f.suptitle(f"Axial stress along the pipe, model III, from the FMI 3.0 output "
               f"stress_pipe_profile ({POINTS} sections): {Q_BLOW / 1e3:.0f} kN held for "
               f"{BLOW * 1e3:.1f} ms", fontsize=10)
    f.tight_layout()
    if data is not None:
        io.write_records(data, records, units={"t": "s", "x": "m", "stress": "Pa"})
    return io.save_png(f, path)
