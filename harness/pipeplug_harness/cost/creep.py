"""Creep of regularised friction while a body should be stuck.

After the closed form's stop time of a body, the body must not move at all: in domains I and III
the pipe is held by the soil while the plug still slides in it (a force below the friction limit
acts on the pipe), and afterwards both are at rest. tanh(v/eps) friction can only balance a force
F < F1 with a velocity, v = eps artanh(F/F1), so the body creeps; the exact solver keeps it still.
"""
from __future__ import annotations

import math

import numpy as np

from pipeplug_references.closed_form import stop_times

from . import core
from .cases import BenchCase
from .regularised import run_regularised
from .sweep import Config, progress

#: the creep window opens this long after the closed form's stop time, s (the regularised
#: velocity decays to its creep value within M eps / F, far shorter)
MARGIN = 1.0e-3


def creep_metrics(result: dict, bench: BenchCase) -> dict:
    """Drift and largest speed of each body after its stop time (+ `MARGIN`) until t_end.

    Returns
    -------
    dict
        ``pipe_creep_m``, ``plug_creep_m`` (m): max |U(t) - U(t_s)|, t_s the first sample of the
        window; ``pipe_residual_v``, ``plug_residual_v`` (m/s): max |V(t)| in the window.
    """
    times, out = bench.times, {}
    for body, stop, (u, v) in zip(("pipe", "plug"), stop_times(bench.case),
                                  (("U1", "V1"), ("U2", "V2"))):
        window = times >= stop + MARGIN
        drift = result[u][window] - result[u][window][0]
        out[f"{body}_creep_m"] = float(np.max(np.abs(drift)))
        out[f"{body}_residual_v"] = float(np.max(np.abs(result[v][window])))
    return out


def creep_speed(bench: BenchCase, eps: float) -> float:
    """Steady creep speed of the pipe while the plug still slides in it, m/s.

    The plug drags the held pipe with F2 < F1; tanh friction balances it at
    F1 tanh(v/eps) = F2, so v = eps artanh(F2/F1). 0 when no plug slides in a stopped pipe.
    """
    pipe_stop, plug_stop = stop_times(bench.case)
    if not plug_stop > pipe_stop or bench.case.F1 == 0.0:
        return 0.0
    return eps * math.atanh(bench.case.F2 / bench.case.F1)


def _creep_row(bench: BenchCase, method: str, eps: float, run, repeats: int) -> dict:
    result, seconds = core.best_time(run, repeats)
    ok = bool(result.get("success", True))
    metrics = creep_metrics(result, bench) if ok else dict.fromkeys(
        ("pipe_creep_m", "pipe_residual_v", "plug_creep_m", "plug_residual_v"), float("nan"))
    progress(f"  creep {method:6s} eps={eps:<8g} {bench.name:4s} pipe drift "
             f"{metrics['pipe_creep_m']:.3g} m, speed {metrics['pipe_residual_v']:.3g} m/s")
    return {"method": method, "eps": eps, "case": bench.name, "wall_s": seconds,
            "success": ok, "creep_speed_theory": creep_speed(bench, eps), **metrics}


def creep_sweep(config: Config, cases: list[BenchCase]) -> list[dict]:
    """The exact solver and tanh-LSODA at every `config.creep_eps` on `cases` (stopping cases)."""
    rows = []
    rtol = config.creep_rtol
    for bench in cases:
        rows.append(_creep_row(bench, "exact", 0.0, lambda b=bench: core.run_exact(b), 1))
        for eps in config.creep_eps:
            rows.append(_creep_row(bench, "LSODA", eps, lambda b=bench, e=eps: run_regularised(
                b, "LSODA", e, rtol, rtol * config.atol_scale), 1))
    return rows
