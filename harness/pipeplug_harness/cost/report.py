"""CSV files and the markdown report of the ``cost`` study."""
from __future__ import annotations

import math
import statistics
from collections import defaultdict

from pipeplug_harness.io import markdown_table

from .front import (
    TARGET,
    aggregate,
    fastest_reaching,
    pareto_front,
    per_case_times,
    times_to_target,
)

#: headline ratios: (family compared with the exact solver, target speed-up or None)
RATIO_TARGETS = (("LSODA", 20.0), ("Radau", 100.0), ("odeint-LSODA", None), ("BDF", None),
                 ("odeint-numba", None), ("CVODE-numba", None), ("numbalsoda", None),
                 ("diffrax-Kvaerno5", None), ("fd-compiled", None))
#: exact against the best regularised setting: target of the median ratio over the cases and
#: of each case's ratio
MEDIAN_TARGET, EACH_TARGET = 50.0, 10.0
#: the exact solver's goal through the single-case API on the compiled path (``build_model``
#: then ``sample`` at a case's 2,000 times), s per case
API_GOAL = 10e-6


def _ms(seconds: float) -> str:
    return "not reached" if math.isnan(seconds) else f"{1e3 * seconds:.3g}"


def _e(value: float) -> str:
    return "failed" if math.isnan(value) else f"{value:.2g}"


def _table(header: list[str], lines: list[list[str]]) -> list[str]:
    return markdown_table(header, lines).splitlines()


def headline(rows: list[dict], families) -> list[str]:
    """Time to reach `TARGET` per family and the speed-ups of the exact solver.

    Besides the time interpolated on each front, the measured time of the first setting below
    `TARGET` is shown: the interpolation assumes settings between two front points exist.
    """
    reached = times_to_target(rows, families)
    in_u = times_to_target(rows, families, key="max_rel_disp_error")
    points = aggregate(rows)
    measured = {(p["method"], p["setting"]): p["wall_s"] for p in points}
    lines = []
    for family, (seconds, setting) in reached.items():
        own = [p for p in points if p["method"] == family]
        best = min((p["max_rel_error"] for p in own if not math.isnan(p["max_rel_error"])),
                   default=math.nan)
        lines.append([family, str(len(own)), _e(best), _ms(seconds), setting or "-",
                      _ms(measured.get((family, setting), math.nan)), _ms(in_u[family][0])])
    text = _table(["method", "settings", "smallest error", f"time to {TARGET:g} [ms]",
                   "first setting below it", "its measured time [ms]",
                   f"time to {TARGET:g} in displacement [ms]"], lines)
    exact = reached.get("exact", (math.nan, ""))[0]
    text.append("")
    for family, target in RATIO_TARGETS:
        if family in reached:
            seconds, setting = reached[family]
            goal = f" (target >= {target:g})" if target else ""
            line = f"- exact vs best {family}: **{_ratio(seconds, exact)}**{goal}"
            if setting:
                line += (f"; with the measured time of its first setting below {TARGET:g}: "
                         f"{_ratio(measured[(family, setting)], exact)}")
            text.append(line)
    return text


def _ratio(seconds: float, exact: float) -> str:
    return "not reached" if math.isnan(seconds) else f"{seconds / exact:.1f}x"


def versus_regularised(rows: list[dict], families) -> tuple[list[str], list[float]]:
    """Per case: the exact solver's time against the fastest regularised setting (any family of
    `families`) that reaches `TARGET` on that case, both measured; then the median and the
    smallest ratio against their targets.

    Returns
    -------
    (list of str, list of float)
        The markdown lines and the ratio of each case (``inf`` where no regularised setting
        reaches `TARGET`).
    """
    best = fastest_reaching(rows, families)
    lines, ratios = [], []
    for mine in (r for r in rows if r["method"] == "exact"):
        r = best.get(mine["case"])
        if r is None:
            ratios.append(math.inf)
            lines.append([mine["case"], _ms(mine["wall_s"]), "none reaches it", "-", "-", "-",
                          "-"])
            continue
        ratios.append(r["wall_s"] / mine["wall_s"])
        lines.append([mine["case"], _ms(mine["wall_s"]), r["method"], r["setting"],
                      _e(r["max_rel_error"]), _ms(r["wall_s"]), f"**{ratios[-1]:.1f}x**"])
    text = _table(["case", "exact [ms]", f"fastest regularised below {TARGET:g}", "setting",
                   "its error", "its time [ms]", "ratio"], lines)
    if ratios:
        text += ["", f"- median ratio over the {len(ratios)} cases: "
                     f"**{statistics.median(ratios):.1f}x** (target >= {MEDIAN_TARGET:g}); "
                     f"smallest: **{min(ratios):.1f}x** (target >= {EACH_TARGET:g} in each case)"]
    times = [r["wall_s"] for r in rows if r["method"] == "exact"]
    if times:
        text += [f"- the exact solver per case: median **{1e6 * statistics.median(times):.1f} "
                 f"µs**, slowest **{1e6 * max(times):.1f} µs** (goal on the compiled path: at "
                 f"most {1e6 * API_GOAL:g} µs per case)"]
    return text, ratios


def versus_compiled(rows: list[dict], families, targets=(TARGET, 1e-9)) -> tuple[list[str],
                                                                              list[float]]:
    """Per case: the exact solver's time against the fastest setting of any compiled competitor
    (`families`) reaching each of `targets`, both measured.

    Returns
    -------
    (list of str, list of float)
        The markdown lines and each case's ratio at the first target (``inf`` where no
        compiled setting reaches it).
    """
    best = {target: fastest_reaching(rows, families, target) for target in targets}
    lines, ratios = [], []
    for mine in (r for r in rows if r["method"] == "exact"):
        line = [mine["case"], _ms(mine["wall_s"])]
        for target in targets:
            r = best[target].get(mine["case"])
            ratio = math.inf if r is None else r["wall_s"] / mine["wall_s"]
            if target == targets[0]:
                ratios.append(ratio)
            line += (["none reaches it", "-", "-"] if r is None else
                     [f"{r['method']}, {r['setting']}", _ms(r["wall_s"]), f"**{ratio:.1f}x**"])
        lines.append(line)
    header = ["case", "exact [ms]"]
    for target in targets:
        header += [f"fastest compiled below {target:g}", "its time [ms]", "ratio"]
    text = _table(header, lines)
    if ratios:
        text += ["", f"- median ratio over the {len(ratios)} cases at {targets[0]:g}: "
                     f"**{statistics.median(ratios):.1f}x**; smallest: **{min(ratios):.1f}x** "
                     f"(the exact solver is {'faster' if min(ratios) > 1.0 else 'NOT faster'} "
                     "than every compiled competitor that reaches it, on every case)"]
    return text, ratios


def same_as_fd(rows: list[dict]) -> str:
    """Whether the compiled fd loop gave the core's fd errors on every case and step."""
    fd = {(r["case"], r["setting"]): (r["max_rel_error"], r["max_rel_disp_error"])
          for r in rows if r["method"] == "fd"}
    mine = [(r["case"], r["setting"], (r["max_rel_error"], r["max_rel_disp_error"]))
            for r in rows if r["method"] == "fd-compiled"]
    if not mine:
        return ""
    differ = [f"{c} {s}" for c, s, e in mine if fd.get((c, s)) != e]
    return ("- fd-compiled against the core's fd scheme: the same errors on every case and step "
            f"({len(mine)} runs)" if not differ else
            f"- fd-compiled differs from the core's fd scheme on: {', '.join(differ)}")


def per_case(rows: list[dict], families) -> list[str]:
    """Time to reach `TARGET` on each case separately, and the ratios to the exact solver."""
    times = per_case_times(rows, families)
    shown = [f for f in families if any(f in t for t in times.values())]
    ratios = [f for f in ("LSODA", "Radau") if f in shown]
    lines = []
    for case, t in times.items():
        lines.append([case] + [_ms(t.get(f, math.nan)) for f in shown]
                     + [_ratio(t.get(f, math.nan), t["exact"]) for f in ratios])
    return _table(["case"] + [f"{f} [ms]" for f in shown] + [f"{f}/exact" for f in ratios], lines)


def fronts(rows: list[dict], families) -> list[str]:
    """The Pareto points of each family (aggregated over the cases)."""
    points, lines = aggregate(rows), []
    for family in families:
        for p in pareto_front([p for p in points if p["method"] == family]):
            lines.append([family, p["setting"], _e(p["max_rel_error"]), _ms(p["wall_s"])])
    return _table(["method", "setting", "max relative error", "total time [ms]"], lines)


def elastic_table(rows: list[dict]) -> list[str]:
    """Model III against the rigid closed form: a model difference, not an error."""
    lines = [[r["case"], r["setting"], _e(r["max_rel_error"]), _e(r["max_rel_disp_error"]),
              _ms(r["wall_s"])] for r in rows]
    return _table(["case", "grid", "velocity difference", "displacement difference",
                   "time [ms]"], lines)


def comm_table(rows: list[dict]) -> list[str]:
    """Per communication step: largest error over the cases and total time, each solver."""
    groups = defaultdict(dict)
    for p in aggregate(rows):
        groups[p["setting"]][p["method"]] = p
    lines = []
    for setting, by in sorted(groups.items(), key=lambda kv: -float(kv[0][2:])):
        lines.append([setting[2:]] + [x for s in ("exact", "fd") for x in (
            _e(by[s]["max_rel_error"]), _ms(by[s]["wall_s"]))])
    return _table(["step h [s]", "exact: error", "exact: time [ms]", "fd (dt = h): error",
                   "fd: time [ms]"], lines)


def creep_table(rows: list[dict]) -> list[str]:
    """Drift and speed of each body after its stop time."""
    lines = [[r["case"], r["method"], "-" if r["method"] == "exact" else f"{r['eps']:g}",
              *(f"{r[k]:.3g}" for k in ("pipe_creep_m", "pipe_residual_v", "creep_speed_theory",
                                        "plug_creep_m", "plug_residual_v"))] for r in rows]
    return _table(["case", "method", "eps [m/s]", "pipe drift [m]", "pipe speed [m/s]",
                   "eps artanh(F2/F1) [m/s]", "plug drift [m]", "plug speed [m/s]"], lines)
