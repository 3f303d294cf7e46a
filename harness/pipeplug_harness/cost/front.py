"""Pareto fronts of error against wall time, and the time a method needs to reach an error.

``key`` names the error measured: ``"max_rel_error"`` (velocities, the headline) or
``"max_rel_disp_error"`` (displacements).
"""
from __future__ import annotations

import math
from collections import defaultdict

#: the headline accuracy: relative error to reach
TARGET = 1.0e-6
ERROR_KEYS = ("max_rel_error", "max_rel_disp_error")
#: smallest relative error reduction for which a slower setting joins a front
FRONT_GAIN = 0.01


def aggregate(rows: list[dict]) -> list[dict]:
    """One point per (method, setting) over all its cases: the largest errors and the total time.

    A setting that failed on any case has NaN errors (it is not a usable choice).
    """
    groups = defaultdict(list)
    for row in rows:
        groups[(row["method"], row["setting"])].append(row)
    points = []
    for (method, setting), group in groups.items():
        point = {"method": method, "setting": setting, "cases": len(group),
                 "wall_s": sum(r["wall_s"] for r in group)}
        for key in ERROR_KEYS:
            errors = [r[key] for r in group]
            point[key] = math.nan if any(math.isnan(e) for e in errors) else max(errors)
        points.append(point)
    return points


def pareto_front(points: list[dict], key: str = "max_rel_error") -> list[dict]:
    """The points no other point beats in both time and error `key`, by increasing time.

    A slower point joins only if it lowers the error by more than `FRONT_GAIN` (a relative
    difference in the last digits is no improvement worth its time).
    """
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p["wall_s"], p[key])):
        if not math.isnan(p[key]) and p[key] < best * (1.0 - FRONT_GAIN):
            front.append(p)
            best = p[key]
    return front


def time_to_error(front: list[dict], target: float = TARGET,
                  key: str = "max_rel_error") -> tuple[float, str]:
    """Time to reach `target` on a front, interpolated log-log between its neighbours.

    Returns
    -------
    (float, str)
        The time, s (NaN if the front never reaches `target`), and the first setting that does.
        The fastest point is taken as is when it is already below `target` (no extrapolation).
    """
    for i, p in enumerate(front):
        if p[key] <= target:
            if i == 0:
                return p["wall_s"], p["setting"]
            q = front[i - 1]
            x = math.log(target / q[key]) / math.log(p[key] / q[key])
            return q["wall_s"] * (p["wall_s"] / q["wall_s"]) ** x, p["setting"]
    return math.nan, ""


def times_to_target(rows: list[dict], families, target: float = TARGET,
                    key: str = "max_rel_error") -> dict:
    """{family: (time s, setting)} on the front of the aggregated `rows` of each family."""
    points = aggregate(rows)
    return {f: time_to_error(pareto_front([p for p in points if p["method"] == f], key),
                             target, key)
            for f in families if any(p["method"] == f for p in points)}


def per_case_times(rows: list[dict], families, target: float = TARGET) -> dict:
    """{case: {family: time s}} to reach `target` in velocity, each case on its own front."""
    out = {}
    for case in dict.fromkeys(r["case"] for r in rows):
        out[case] = {f: t for f, (t, _) in times_to_target(
            [r for r in rows if r["case"] == case], families, target).items()}
    return out


def fastest_reaching(rows: list[dict], families, target: float = TARGET) -> dict:
    """{case: row} of the fastest measured setting of `families` whose velocity error on that
    case is at most `target` (cases no setting reaches are left out)."""
    best = {}
    for r in rows:
        if r["method"] in families and r["max_rel_error"] <= target:
            if r["case"] not in best or r["wall_s"] < best[r["case"]]["wall_s"]:
                best[r["case"]] = r
    return best
