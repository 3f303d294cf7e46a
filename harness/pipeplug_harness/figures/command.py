"""``pipeplug figures``: the paper's Figs. 3, 4, 5, 6a, 6b and 7 redrawn from FMU runs, and
with ``--fmi 3`` the axial stress along the pipe from the FMI 3.0 profile arrays
(``stress``, :mod:`~pipeplug_harness.figures.stress`).

Parameters come from the captions and the text (section 3; docs/corrections.md C1-C8, D1, F). Each panel
shows the FMU's pipe velocity (solid) and plug velocity (dash-dot) with the reference overlaid
(thin black dotted: the closed form of model I; for model II, which has no closed form, the
exact solver run with a 10x finer communication step), the event times t0...t7 as vertical
dashed lines and the paper's levels U*, U** as horizontal dashed lines.
"""
from __future__ import annotations

import argparse
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from pipeplug_harness import io
from pipeplug_harness.errors import UserError
from pipeplug_harness.figures.stress import draw_stress_profiles
from pipeplug_harness.fmus import add_fmi_argument, find_fmu
from pipeplug_harness.load import Load
from pipeplug_harness.paper import T_FIG7
from pipeplug_harness.session import fmi_version, simulate
from pipeplug_references import closed_form as cf

BASE = cf.Case()
MPA = 1e6
FIGURES = ("3", "4", "5", "6a", "6b", "7", "stress")
FMI3_ONLY = ("stress",)               # drawn from the profile arrays of the FMI 3.0 FMU


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--fmu", help="the FMU (default: the build of this installation, made "
                                      "once into the user's cache)")
    parser.add_argument("--out", default="out/figures", help="output folder (%(default)s)")
    parser.add_argument("--only", nargs="*", default=None, choices=FIGURES, metavar="FIGURE",
                        help=f"figures to draw, among {' '.join(FIGURES)} (default: all; "
                             f"{', '.join(FMI3_ONLY)} with --fmi 3 only)")
    add_fmi_argument(parser)


def _label(case: cf.Case) -> str:
    return f"τ1={case.tau1 / MPA:.4g}, τ2={case.tau2 / MPA:.4g} MPa"


def _rigid_run(fmu, case: cf.Case, options: dict, step: float = 5e-4, stop: float = 0.3):
    params = {"tau1": case.tau1, "tau2": case.tau2, **options}
    return simulate(fmu, params, Load.from_pulses([(0.0, case.t0, case.Q0)]), step, stop)


def _levels(fig: str) -> dict[str, float]:
    """The paper's horizontal levels U* and U** (docs/corrections.md C4) [m/s]."""
    u_pipe = BASE.Q0 * BASE.t0 / BASE.M1
    u_both = BASE.Q0 * BASE.t0 / (BASE.M1 + BASE.M2)
    u2 = lambda alpha: BASE.Q0 * BASE.t0 * BASE.beta / BASE.M2 / (BASE.gamma + alpha)  # noqa
    return {"4": {"U*": u_pipe, "U** (α=2)": u2(2)}, "5": {"U*": u_both},
            "6a": {"U*": u_pipe, "U** (α=1)": u2(1)}}.get(fig, {})


def _draw_rigid(ax, fig: str, cases: list[cf.Case], growth: bool, fmu) -> None:
    colors = [f"C{i}" for i in range(10)]
    for i, case in enumerate(cases):
        res = _rigid_run(fmu, case, {"contact_growth": growth})
        t = res["time"] * 1e3
        ax.plot(t, res["v_pipe"], "-", color=colors[i], lw=1.6, label=f"{i + 1}: {_label(case)}")
        ax.plot(t, res["v_plug"], "-.", color=colors[i], lw=1.3)
        if growth:
            ref = _rigid_run(fmu, case, {"contact_growth": True}, step=5e-5)
            ax.plot(ref["time"] * 1e3, ref["v_pipe"], ":", color="k", lw=0.8)
            ax.plot(ref["time"] * 1e3, ref["v_plug"], ":", color="k", lw=0.8)
            _mark_mode_changes(ax, ref, colors[i])
            continue
        tt = np.linspace(0.0, 0.3, 3001)
        sol = cf.solution(case, tt)
        ax.plot(tt * 1e3, sol["V1"], ":", color="k", lw=0.8)
        ax.plot(tt * 1e3, sol["V2"], ":", color="k", lw=0.8)
        for name, te in cf.event_times(case).items():
            if name == "t4" and case.tau2 == 0.0:
                continue                  # the plug never moves: no plug stop to mark
            if te is not None and math.isfinite(te) and te <= 0.3:
                ax.axvline(te * 1e3, color=colors[i], ls="--", lw=0.6, alpha=0.7)
    for name, level in _levels(fig).items():
        ax.axhline(level, color="gray", ls="--", lw=0.8)
        ax.text(2, level, name, ha="left", va="bottom", fontsize=8, color="gray")


def _mark_mode_changes(ax, res: np.ndarray, color: str) -> None:
    """Mark the event times of a run without closed form: where a contact mode changes."""
    modes = np.column_stack([res["pipe_mode"], res["plug_mode"]])
    changed = np.flatnonzero(np.any(modes[1:] != modes[:-1], axis=1)) + 1
    for i in changed:
        ax.axvline(res["time"][i] * 1e3, color=color, ls="--", lw=0.6, alpha=0.7)


def _fig6_cases() -> list[cf.Case]:
    return cf.figure_cases()["6a"]


RIGID = {
    "3": ("Fig. 3 (model I): τ1 = τ*/(γ+1)", lambda: cf.figure_cases()["3"], False),
    "4": ("Fig. 4 (model I): τ1 = 2 τ2", lambda: cf.figure_cases()["4"], False),
    "5": ("Fig. 5 (model I): τ1 = 0", lambda: cf.figure_cases()["5"], False),
    "6a": ("Fig. 6a (model I): τ1 = τ2", _fig6_cases, False),
    "6b": ("Fig. 6b (model II, contact min(max(U1,0),L1)): τ1 = τ2", _fig6_cases, True),
}


def draw_rigid_figure(fig: str, path: Path, fmu) -> Path:
    """Draw one of the rigid-model figures at ``path``; returns it."""
    title, make_cases, growth = RIGID[fig]
    f, ax = io.subplots(figsize=(8, 5))
    _draw_rigid(ax, fig, make_cases(), growth, fmu)
    ax.set(xlabel="t [ms]", ylabel="velocity [m/s]", xlim=(0, 300), title=title)
    ref = "exact solver, 10x finer step" if growth else "closed form"
    ax.plot([], [], "k-", label="pipe (FMU)")
    ax.plot([], [], "k-.", label="plug (FMU)")
    ax.plot([], [], "k:", label=f"reference ({ref})")
    ax.plot([], [], "k--", lw=0.6, label="event times" + (" (mode changes)" if growth else ""))
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    f.tight_layout()
    return io.save_png(f, path)


def draw_fig7(path: Path, fmu) -> Path:
    """Fig. 7 at ``path``: pipe velocity at x = L1/2, elastic model III vs rigid model I
    (docs/corrections.md D1)."""
    case = replace(BASE, tau1=0.0, tau2=1e4)
    load = Load.from_pulses([(0.0, case.t0, case.Q0)])
    elastic = simulate(fmu, {"tau1": 0.0, "tau2": 1e4, "elastic": True, "dx": 0.01,
                             "courant": 1.0, "x_monitor": 0.5, "E1": 1.95e11, "E2": 6.0e8},
                       load, 2e-5, T_FIG7)
    t = elastic["time"]
    rigid = cf.solution(case, t)
    peak_e, peak_r = elastic["v_pipe"].max(), rigid["V1"].max()
    f, (ax, zoom) = io.subplots(1, 2, figsize=(11, 4.5), gridspec_kw={"width_ratios": [2, 1]})
    for a in (ax, zoom):
        a.plot(t * 1e3, elastic["v_pipe"], "-", lw=1.0, label="model III (elastic), x = L1/2")
        a.plot(t * 1e3, rigid["V1"], "-.", lw=1.4, color="C3", label="model I (rigid)")
        a.set(xlabel="t [ms]", ylabel="pipe velocity [m/s]")
        a.grid(alpha=0.3)
    zoom.set(xlim=(44, 56), ylim=(peak_r * 0.97, peak_e * 1.005), title="around the peak")
    ax.set_title(f"Fig. 7: τ1 = 0, τ2 = 0.01 MPa; peak III {peak_e:.3f} m/s, "
                 f"peak I {peak_r:.3f} m/s ({(peak_r - peak_e) / peak_e:+.3%})", fontsize=9)
    ax.legend(fontsize=8)
    f.tight_layout()
    return io.save_png(f, path)


def main(args: argparse.Namespace) -> int:
    figures = args.only or [f for f in FIGURES if args.fmi == 3 or f not in FMI3_ONLY]
    for fig in figures:
        if fig in FMI3_ONLY and args.fmi != 3:
            raise UserError(key="--only", value=fig, allowed="with --fmi 3 (it is drawn from "
                                                             "the FMI 3.0 profile arrays)")
    fmu = find_fmu(args.fmu, fmi=args.fmi)
    fmi_version(fmu, args.fmi)
    with io.OutputFolder(args.out, "figures") as out:
        for fig in figures:
            target = out.file(f"fig{fig}.png" if fig not in FMI3_ONLY else f"{fig}_profile.png")
            if fig == "7":
                path = draw_fig7(target, fmu)
            elif fig == "stress":
                path = draw_stress_profiles(target, fmu, out.file("stress_profile.csv"))
            else:
                path = draw_rigid_figure(fig, target, fmu)
            print(f"wrote {path}", flush=True)
    return 0
