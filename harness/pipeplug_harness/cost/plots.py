"""Plots of the ``cost`` study: the Pareto plot and the creep plot."""
from __future__ import annotations

import math
from pathlib import Path

from pipeplug_harness import io

from .front import TARGET, aggregate, pareto_front

#: marker and colour of each family
STYLE = {"exact": ("*", "black"), "fd": ("s", "tab:blue"), "LSODA": ("o", "tab:orange"),
         "odeint-LSODA": ("D", "tab:red"), "Radau": ("^", "tab:green"), "BDF": ("v", "tab:purple"),
         "odeint-numba": ("D", "tab:brown"), "CVODE-numba": ("P", "tab:pink"),
         "numbalsoda": ("X", "tab:olive"), "diffrax-Kvaerno5": ("h", "tab:cyan")}


def pareto_plot(rows: list[dict], families, n_cases: int, path: Path) -> None:
    """Largest error over the cases against their total wall time, log-log, one style per family.

    Every setting is a faint marker; each family's Pareto front is joined by a line.
    """
    fig, ax = io.subplots(figsize=(9.5, 5.0))
    points = aggregate(rows)
    for family in families:
        own = [p for p in points if p["method"] == family and not math.isnan(p["max_rel_error"])]
        if not own:
            continue
        marker, colour = STYLE.get(family, ("x", "gray"))
        ax.scatter([p["wall_s"] for p in own], [p["max_rel_error"] for p in own], marker=marker,
                   color=colour, alpha=0.3, s=22)
        front = pareto_front(own)
        ax.plot([p["wall_s"] for p in front], [p["max_rel_error"] for p in front], marker=marker,
                color=colour, label=family, markersize=8 if family == "exact" else 5)
    ax.axhline(TARGET, color="gray", linestyle=":", label=f"relative error {TARGET:g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"wall time for the {n_cases} cases [s] (model build included, best of repeats)")
    ax.set_ylabel("max |V - V_exact| / max |V1_exact| (pipe and plug) [-]")
    ax.set_title("What accuracy costs: rigid models I and II, rectangular pulse\n"
                 "(lines: Pareto front of each method; faint markers: every setting)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))   # off every point
    fig.tight_layout()
    io.save_png(fig, path, dpi=120)


def creep_plot(rows: list[dict], path: Path) -> None:
    """Drift (left) and speed (right) of the held pipe against eps, log-log.

    Only the cases where a force acts on the stopped pipe (the plug still slides in it) creep;
    in the others the regularised velocity decays and nothing is drawn (see the table).
    """
    fig, axes = io.subplots(1, 2, figsize=(10.0, 4.2))
    reg = [r for r in rows if r["method"] != "exact" and r["creep_speed_theory"] > 0.0
           and r["pipe_creep_m"] > 0.0]
    cases = list(dict.fromkeys(r["case"] for r in reg))
    quantities = (("pipe_creep_m", "pipe drift after its stop time [m]"),
                  ("pipe_residual_v", "largest pipe speed after its stop time [m/s]"))
    for ax, (key, label) in zip(axes, quantities):
        for i, case in enumerate(cases):
            own = sorted((r for r in reg if r["case"] == case), key=lambda r: r["eps"])
            ax.plot([r["eps"] for r in own], [r[key] for r in own], marker="os^v"[i % 4],
                    linestyle="-" if i % 2 == 0 else "--", markersize=7 - 2 * (i % 2),
                    label=f"tanh + LSODA, domain {case}")
        if key == "pipe_residual_v" and reg:
            own = sorted((r for r in reg if r["case"] == cases[0]), key=lambda r: r["eps"])
            ax.plot([r["eps"] for r in own], [r["creep_speed_theory"] for r in own], ":",
                    color="black", label="eps artanh(F2/F1) (steady creep)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("regularisation velocity eps [m/s]")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.text(0.03, 0.95, "exact solver: exactly 0 m and 0 m/s\n(not drawable on log axes)",
                transform=ax.transAxes, fontsize=8, va="top")
        ax.legend(fontsize=8, loc="lower right")
    fig.suptitle("Creep of regularised friction: the pipe is held by the soil while the plug "
                 "still slides in it", fontsize=11)
    fig.tight_layout()
    io.save_png(fig, path, dpi=120)
