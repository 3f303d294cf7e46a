"""Probabilistic drivability: what a sample of drives says, with its standard errors.

Each row of a drive sweep is one drive (``outcome``: "target", "static" or "set" refusal,
"max_blows"). Over ``n`` independent samples:

* probability of refusal ``p = refusals / n``, standard error ``sqrt(p (1 - p) / n)`` (the
  binomial proportion; when no sample or every sample refuses, the rule of three bounds it:
  ``p < 3 / n`` at 95 %);
* blows to drive, over the ``m`` drives reaching the target: mean with standard error
  ``sd / sqrt(m)``, and quantiles (a quantile's standard error, by the order statistics'
  binomial spread, is shown as the 95 % range of ranks ``m q +- 1.96 sqrt(m q (1 - q))``).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from pipeplug_harness import io
from pipeplug_harness.errors import UserError

__all__ = ["summarise", "report", "plot_blows"]

_QUANTILES = (0.05, 0.25, 0.5, 0.75, 0.95)


def summarise(table, names=()) -> dict:
    """The numbers of the report from a drive sweep's rows (``names``: varied columns kept
    per drive, under ``"values"``)."""
    rows = table.select(["outcome", "blows", "penetration", "error", *names]).to_pydict()
    ok = [i for i, e in enumerate(rows["error"]) if not e]
    outcome = np.array([rows["outcome"][i] for i in ok])
    blows = np.array([rows["blows"][i] for i in ok], dtype=float)
    n = len(ok)
    refused = np.isin(outcome, ("static", "set"))
    p = float(refused.mean()) if n else math.nan
    driven = blows[outcome == "target"]
    m = len(driven)
    out = {"n": n, "errors": len(rows["error"]) - n, "p_refusal": p,
           "se_refusal": math.sqrt(p * (1.0 - p) / n) if n else math.nan,
           "refusals": int(refused.sum()), "driven": m,
           "max_blows": int((outcome == "max_blows").sum()), "blows_driven": driven,
           "refusal_depth": np.array([rows["penetration"][i] for i in ok])[refused],
           "outcomes": outcome, "blows": blows,
           "values": {k: np.array([rows[k][i] for i in ok]) for k in names}}
    if m:
        out["mean_blows"] = float(driven.mean())
        out["se_mean_blows"] = float(driven.std(ddof=1) / math.sqrt(m)) if m > 1 else math.nan
        # a quantile of whole blows is a number of blows: the sample's own value (the
        # inverse of its distribution function), never one between two drives
        out["quantiles"] = {q: float(np.quantile(driven, q, method="inverted_cdf"))
                            for q in _QUANTILES}
        out["quantile_ranges"] = {q: _quantile_range(np.sort(driven), q) for q in _QUANTILES}
    return out


def _quantile_range(ordered: np.ndarray, q: float) -> tuple[float, float]:
    m = len(ordered)
    half = 1.96 * math.sqrt(m * q * (1.0 - q))
    lo, hi = int(max(0, math.floor(m * q - half))), int(min(m - 1, math.ceil(m * q + half)))
    return float(ordered[lo]), float(ordered[hi])


def check_applies(spec) -> None:
    """Refuse, before the run, a sweep this report does not apply to: one of blows.

    Raises
    ------
    UserError
        Naming ``report = "drivability"`` and what it needs.
    """
    if spec.kind != "drive":
        raise UserError(key="report", value="drivability", allowed='a sweep of drives (kind = '
                                                                 '"drive")')


def report(spec, table, figure: Path) -> str:
    """The summary text; draws the distribution of blows to drive."""
    check_applies(spec)
    s = summarise(table, [d.name for d in spec.dims][:2])
    n = s["n"]
    lines = [f"drivability: {n} drives ({', '.join(_described(d) for d in spec.dims)})"]
    if s["errors"]:
        lines.append(f"  {s['errors']} case(s) failed and are left out (the 'error' column)")
    if s["refusals"] in (0, n):
        bound = f"(rule of three: {'< ' if s['refusals'] == 0 else '> 1 - '}{3.0 / n:.2g} at 95 %)"
    else:
        bound = ""
    lines.append(f"  P(refusal) = {s['p_refusal']:.4f} +- {s['se_refusal']:.4f} (standard error; "
                 f"{s['refusals']} of {n}) {bound}".rstrip())
    if s["max_blows"]:
        lines.append(f"  {s['max_blows']} drive(s) stopped at max_blows without refusal")
    if s["driven"]:
        q = s["quantiles"]
        lines.append(f"  blows to drive ({s['driven']} drives reaching the target): mean "
                     f"{s['mean_blows']:.3f} +- {s['se_mean_blows']:.3f} (standard error)")
        lines.append("  quantiles: " + ", ".join(
            f"{int(k * 100)} % {v:g} [{s['quantile_ranges'][k][0]:g}, "
            f"{s['quantile_ranges'][k][1]:g}]" for k, v in q.items())
            + " (95 % ranges)")
    if s["refusals"]:
        depth = s["refusal_depth"]
        lines.append(f"  refusal depth: median {np.median(depth):.3g} m, range "
                     f"{depth.min():.3g}-{depth.max():.3g} m")
    plot_blows(figure, spec, s)
    lines.append(f"  wrote {figure}")
    return "\n".join(lines)


def _described(d) -> str:
    if d.values is not None:
        return f"{d.name}: {len(d.values)} values"
    from .sample import DISTRIBUTIONS
    keys = DISTRIBUTIONS[d.dist].keys
    return f"{d.name} ~ {d.dist}(" + ", ".join(f"{k}={v:g}" for k, v in zip(keys, d.args)) + ")"


def plot_blows(path: Path, spec, s: dict) -> Path:
    """Histogram of blows to drive; beside it each drive over the first two varied names,
    coloured by its blows, refusals marked."""

    fig, (ax, bx) = io.subplots(1, 2, figsize=(11.0, 4.4), dpi=120,
                                 gridspec_kw={"width_ratios": (1.1, 1.0)})
    _scatter(fig, bx, s)
    driven = s["blows_driven"]
    if len(driven):
        top = int(driven.max())
        width = max(1, math.ceil(top / 60))
        # edges from 0.5 past the largest count: every drive falls in a bin, the longest too
        bins = 0.5 + width * np.arange(math.ceil(top / width) + 1)
        ax.hist(driven, bins=bins, color="#4c72b0", label=f"target reached ({s['driven']})")
        ax.axvline(s["mean_blows"], color="k", lw=1.2, ls="--",
                   label=f"mean {s['mean_blows']:.2f} +- {s['se_mean_blows']:.2f}")
        ax.legend(fontsize=8)           # none when no drive reached the target: nothing to name
    ax.set_xlabel("blows to drive")
    ax.set_ylabel("drives")
    fig.suptitle(f"{spec.name}: {s['n']} drives; P(refusal) = {s['p_refusal']:.4f} +- "
                 f"{s['se_refusal']:.4f} (standard error)\n"
                 + "; ".join(_described(d) for d in spec.dims), fontsize=9)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    return io.save_png(fig, path, dpi=fig.dpi)


def _scatter(fig, ax, s: dict) -> None:
    names = list(s["values"])
    if len(names) < 2:
        ax.set_axis_off()
        return
    x, y = (s["values"][k] for k in names)
    target = s["outcomes"] == "target"
    art = ax.scatter(x[target], y[target], c=s["blows"][target], s=3, cmap="viridis",
                     rasterized=True)
    refused = np.isin(s["outcomes"], ("static", "set"))
    ax.scatter(x[refused], y[refused], s=4, c="#d62728", marker="x", lw=0.6,
               label=f"refusal ({int(refused.sum())})", rasterized=True)
    fig.colorbar(art, ax=ax, label="blows to drive")
    from pipeplug.params import PARAMETERS
    units = {p.name: p.unit for p in PARAMETERS}
    ax.set_xlabel(f"{names[0]} [{units.get(names[0], 'SI')}]")
    ax.set_ylabel(f"{names[1]} [{units.get(names[1], 'SI')}]")
    ax.ticklabel_format(style="sci", scilimits=(-3, 3))
    ax.legend(fontsize=8, loc="upper left")
