"""Benchmark of the elastic model without numba against the numpy reference of its scheme.

Run ``python -m benchmarks.elastic_numpy`` (``--repeat R`` timed rounds). Two
scenes of 0.08 s, one 23 kN blow of 50 ms, dx = 1 cm, Courant 1 (40,000 internal steps):

* Fig. 7: pipe and plug of 100 cells each, plug friction only (the paper's scene);
* every effect: plug friction and soil friction over the penetrated length (tau1 = 20 kPa,
  tau2 = 10 kPa, contact growth).

For each scene it times, in one process,

(a) the core's path without numba, as a host without numba (or with ``PIPEPLUG_NO_JIT=1``) runs
    it: whole-array numpy steps through ``advance``;
(b) the numpy-per-step reference of the same scheme (:mod:`.elastic_reference`, which never
    imports the core) on a model's own arrays;

alternating chunk by chunk (1 ms of simulated time, 500 internal steps, each), so that the
shared machine's changing load falls on both alike. It prints the best total seconds of each
over the rounds, the ratio (a)/(b) of the bests (target <= 1.5) with the range of the rounds'
ratios, and the largest field difference of (a) from the compiled loops (when numba is enabled)
and from (b), relative to each field's size.
"""
from __future__ import annotations

import argparse
import sys
import time

from pipeplug import Options, Params, jit
from pipeplug.elastic.model import ElasticModel

from .effects import FULL
from .elastic import disagreement
from .elastic_reference import run_numpy, run_numpy_full

#: scene name -> (parameter changes, contact growth, numpy reference)
SCENES = {
    "Fig. 7 (plug friction)": ({}, False, run_numpy),
    "every effect (plug, soil, growth)": (FULL, True, run_numpy_full),
}


def elastic_model(changes: dict, growth: bool, vectorised: bool) -> ElasticModel:
    """A fresh elastic model of a scene at dx = 1 cm, on the chosen path."""
    options = Options(elastic=True, contact_growth=growth)
    params = Params.from_mapping(dict(changes, dx=0.01))
    params.validate(options.active_groups())
    return ElasticModel(params, options, vectorised=vectorised)


def chunks() -> list[tuple[float, float]]:
    """The scene as (Q [N], h [s]) chunks of 1 ms: the blow, then the rest after it."""
    from pipeplug_harness.figures.fig7 import Q0, T0, T_END
    h = 1e-3
    return [(Q0, h)] * round(T0 / h) + [(0.0, h)] * round((T_END - T0) / h)


def one_round(changes: dict, growth: bool, reference) -> tuple[float, float, object, object]:
    """Seconds of (a) and (b) over the scene, chunk by chunk alternately; both models."""
    core = elastic_model(changes, growth, vectorised=True)
    ref = elastic_model(changes, growth, vectorised=True)   # only its arrays are used
    g = ref.grid
    arrays = (g.coef, ref.v1, ref.N1, ref.v2, ref.N2, g.cells1, ref.u1, g.cells2, ref.u2,
              ref.acc)
    t_core = t_ref = 0.0
    for q, h in chunks():
        start = time.perf_counter()
        core.advance(q, h)
        middle = time.perf_counter()
        n = ref.steps_for(h)
        reference(n, h / n, q, *arrays)
        t_core += middle - start
        t_ref += time.perf_counter() - middle
    return t_core, t_ref, core, ref


def compare(changes: dict, growth: bool, reference, repeat: int) -> dict:
    """Timings [s] of (a) and (b) and the agreement figures of one scene."""
    rounds = [one_round(changes, growth, reference) for _ in range(repeat)]
    core, ref = rounds[-1][2:]
    res = {"core": min(r[0] for r in rounds), "reference": min(r[1] for r in rounds),
           "ratios": [r[0] / r[1] for r in rounds], "vs_reference": disagreement(core, ref)}
    if jit.enabled():
        compiled = elastic_model(changes, growth, vectorised=False)
        for q, h in chunks():
            compiled.advance(q, h)
        res["vs_compiled"] = disagreement(core, compiled)
    return res


def main(argv=None) -> int:
    """Command-line entry point."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed rounds (best kept)")
    args = parser.parse_args(argv)
    print("0.08 s, dx = 1 cm, Courant 1: 40,000 internal steps; best of "
          f"{args.repeat} rounds, (a) and (b) alternating every 1 ms of simulated time")
    print("| scene | (a) core without numba [s] | (b) numpy reference [s] | (a)/(b) "
          "| rounds | target | (a) vs compiled | (a) vs (b) |")
    print("|---|---|---|---|---|---|---|---|")
    for name, (changes, growth, reference) in SCENES.items():
        r = compare(changes, growth, reference, args.repeat)
        compiled = f"{r['vs_compiled']:.1e}" if "vs_compiled" in r else "(no numba)"
        print(f"| {name} | {r['core']:.2f} | {r['reference']:.2f} "
              f"| {r['core'] / r['reference']:.2f} "
              f"| {min(r['ratios']):.2f}-{max(r['ratios']):.2f} | <= 1.5 "
              f"| {compiled} | {r['vs_reference']:.1e} |", flush=True)
    print("differences: largest field difference / field size (v, N, u of pipe and plug; works)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
