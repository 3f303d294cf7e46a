"""The paper's Fig. 2 from runs: (tau1, tau2) points classified by the modes their runs went
through, against the analytic domains.

Model I under one rectangular pulse (paper, section 1; docs/corrections.md) has five solution
domains, each with its own sequence of contact modes ``(pipe_mode, plug_mode)`` =
``(sign U1', sign(U1' - U2'))`` (:data:`SEQUENCES`). Each run is classified by the sequence the
core reports; the analytic domain comes from the independent closed form
(:func:`pipeplug_references.closed_form.domain`), whose boundaries are the lines tau1 = gamma
tau2, tau1 + gamma tau2 = tau* (both for tau1 < tau*) and tau1 = tau*. A point within
:data:`~pipeplug_references.closed_form.BOUNDARY_RTOL` tau* of a boundary counts as on it: its
run may show the sequence of either side or another one (a mode lasting no time); any other
difference is a disagreement and is listed.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pipeplug.params import Params
from pipeplug_harness import io
from pipeplug_harness.errors import UserError
from pipeplug_harness.paper import RIGID_PARAMETERS
from pipeplug_references import closed_form as cf

__all__ = ["SEQUENCES", "classify", "report", "plot_domains"]

#: mode sequence (as in the sweep's ``modes`` column) -> the paper's domain
SEQUENCES = {
    "(1,1),(1,-1),(0,-1),(0,0)": "I",     # both slide; the plug overtakes; pipe, then plug stop
    "(1,1),(1,0),(0,0)": "II",            # both slide; they stick; they stop together
    "(1,0),(1,-1),(0,-1),(0,0)": "III",   # together; the plug overtakes after t0; pipe, plug stop
    "(1,0),(0,0)": "IV",                  # together until they stop
    "(0,0)": "V",                         # nothing moves
}
_NAMES = ("I", "II", "III", "IV", "V")


def _case(spec, tau1: float, tau2: float) -> cf.Case:
    """The closed form's case of a point: the sweep's base pipe, plug and blow."""
    base, blows = spec.base, spec.base["blows"]
    fields = [k for k in RIGID_PARAMETERS if not k.startswith("tau")]
    given = {k: base[k] if base.get(k) is not None else getattr(Params(), k) for k in fields}
    return cf.Case(**given, tau1=tau1, tau2=tau2, Q0=blows["amplitude"], t0=blows["duration"])


def check_applies(spec) -> None:
    """Refuse, before the run, a sweep this report does not apply to.

    Raises
    ------
    UserError
        Naming ``report = "domains"`` and what it needs.
    """
    base = spec.base
    names = {d.name for d in spec.dims}
    problems = []
    if spec.kind != "blow" or base["blows"]["count"] != 1:
        problems.append("single blows (kind = \"blow\", count = 1)")
    if base.get("contact_growth") or base.get("elastic") is not False or \
            base.get("solver") not in (None, "exact"):
        problems.append("model I, rigid, exact ([soil] contact_growth = false, [model] "
                        "elastic = false)")
    if spec.sampling != "grid" or names != {"tau1", "tau2"}:
        problems.append("a [grid] over tau1 and tau2 only")
    if problems:
        raise UserError(key="report", value="domains", allowed="a sweep of " + "; ".join(problems))


def on_boundary(case: cf.Case) -> bool:
    """True within BOUNDARY_RTOL tau* of a domain boundary."""
    tol, ts = cf.BOUNDARY_RTOL * case.tau_star, case.tau_star
    g, t1, t2 = case.gamma, case.tau1, case.tau2
    inside = t1 < ts + tol
    return bool(abs(t1 - ts) <= tol or (inside and (abs(t1 - g * t2) <= tol
                                                    or abs(t1 + g * t2 - ts) <= tol)))


def classify(spec, table) -> list[dict]:
    """Per point: tau1, tau2, the modes, the domain they say (or "other"), the analytic domain,
    whether it is on a boundary."""
    rows = []
    for r in table.select(["case", "tau1", "tau2", "modes", "error"]).to_pylist():
        case = _case(spec, r["tau1"], r["tau2"])
        rows.append({**r, "seen": SEQUENCES.get(r["modes"], "other"),
                     "expected": cf.domain(case), "boundary": on_boundary(case)})
    return rows


def report(spec, table, figure: Path) -> str:
    """Classify, list the disagreements, draw the map; the summary text."""
    check_applies(spec)
    rows = classify(spec, table)
    case = _case(spec, 0.0, 0.0)
    agree = [r for r in rows if r["seen"] == r["expected"]]
    boundary = [r for r in rows if r["seen"] != r["expected"] and r["boundary"]]
    wrong = [r for r in rows if r["seen"] != r["expected"] and not r["boundary"]]
    counts = {n: sum(r["seen"] == n for r in rows) for n in (*_NAMES, "other")}
    lines = [f"domains: {len(rows)} points; tau* = {case.tau_star:.6g} Pa, gamma = "
             f"{case.gamma:.6g}, beta = {case.beta:.6g}",
             "  by mode sequence: " + ", ".join(f"{k} {v}" for k, v in counts.items()),
             f"  agree with the analytic domain: {len(agree)}; on a boundary (within "
             f"{cf.BOUNDARY_RTOL:g} tau*) and different: {len(boundary)}; disagreements: "
             f"{len(wrong)}"]
    for r in boundary:
        lines.append(f"    on a boundary: tau1 = {r['tau1']!r}, tau2 = {r['tau2']!r}: "
                     f"{r['modes']} ({r['seen']}), analytic {r['expected']}")
    for r in wrong:
        lines.append(f"    DISAGREEMENT: tau1 = {r['tau1']!r}, tau2 = {r['tau2']!r}: "
                     f"{r['modes'] or r['error']} ({r['seen']}), analytic {r['expected']}")
    plot_domains(figure, spec, rows, case)
    lines.append(f"  wrote {figure}")
    return "\n".join(lines)


_COLOURS = {"I": "#8fbbda", "II": "#f7b77f", "III": "#95cf95", "IV": "#e99c9c", "V": "#c5b0d5",
            "other": "#444444"}


def _edges(centres: np.ndarray) -> np.ndarray:
    mid = 0.5 * (centres[1:] + centres[:-1])
    first = centres[0] - (mid[0] - centres[0]) if len(mid) else centres[0] - 0.5
    last = centres[-1] + (centres[-1] - mid[-1]) if len(mid) else centres[0] + 0.5
    return np.concatenate([[first], mid, [last]])


def plot_domains(path: Path, spec, rows: list, case: cf.Case) -> Path:
    """The map: each point's cell coloured by its mode sequence's domain, the analytic
    boundaries over it, disagreements marked."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    dims = {d.name: np.asarray(d.values, dtype=float) for d in spec.dims}
    t1s, t2s = np.unique(dims["tau1"]), np.unique(dims["tau2"])
    labels = (*_NAMES, "other")
    grid = np.full((len(t2s), len(t1s)), np.nan)
    for r in rows:
        grid[np.searchsorted(t2s, r["tau2"]), np.searchsorted(t1s, r["tau1"])] = \
            labels.index(r["seen"])
    mpa = 1e-6
    fig, ax = io.subplots(figsize=(7.0, 5.6), dpi=120)
    ax.pcolormesh(_edges(t1s) * mpa, _edges(t2s) * mpa, grid,
                  cmap=ListedColormap([_COLOURS[k] for k in labels]), vmin=-0.5,
                  vmax=len(labels) - 0.5, shading="flat")
    ts, g = case.tau_star * mpa, case.gamma
    top = t2s[-1] * mpa
    style = dict(color="k", lw=1.6)
    ax.plot([0.0, ts], [0.0, ts / g], **style, ls="-",
            label=r"$\tau_1 = \gamma\tau_2$")
    ax.plot([0.0, ts], [ts / g, 0.0], **style, ls="--",
            label=r"$\tau_1 + \gamma\tau_2 = \tau_*$")
    ax.plot([ts, ts], [0.0, max(top, ts / g)], **style, ls=":", label=r"$\tau_1 = \tau_*$")
    wrong = [r for r in rows if r["seen"] != r["expected"] and not r["boundary"]]
    if wrong:
        ax.plot([r["tau1"] * mpa for r in wrong], [r["tau2"] * mpa for r in wrong], "rx",
                ms=7, label=f"disagreements ({len(wrong)})")
    for name in _NAMES:                     # each label at the middle of its points
        pts = [(r["tau1"], r["tau2"]) for r in rows if r["seen"] == name]
        if pts:
            x, y = np.median(np.array(pts), axis=0) * mpa
            ax.text(x, y, name, ha="center", va="center", fontsize=15, weight="bold")
    ax.set_xlim(_edges(t1s)[[0, -1]] * mpa)
    ax.set_ylim(_edges(t2s)[[0, -1]] * mpa)
    ax.set_xlabel(r"$\tau_1$ [MPa] (soil on the pipe)")
    ax.set_ylabel(r"$\tau_2$ [MPa] (plug on the pipe)")
    b = spec.base["blows"]
    ax.set_title(f"Domains of solution (paper's Fig. 2) from {len(rows)} runs: model I, "
                 f"{b['amplitude'] / 1e3:g} kN for {b['duration'] * 1e3:g} ms\n"
                 r"cells: the mode sequence each run went through; lines: analytic boundaries "
                 rf"($\tau_*$ = {case.tau_star / 1e3:.4g} kPa, $\gamma$ = {case.gamma:.4g})",
                 fontsize=9)
    handles, _ = ax.get_legend_handles_labels()
    handles += [Patch(color=_COLOURS[k], label=k) for k in labels
                if k != "other" or any(r["seen"] == "other" for r in rows)]
    ax.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9, ncol=2)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    return io.save_png(fig, path, dpi=fig.dpi)
