"""Benchmark of the elastic model without numba against the numpy reference of its scheme.

Run ``python -m pipeplug_harness.bench.elastic_numpy`` (``--repeat R`` timed rounds). Two
scenes of 0.08 s, one 23 kN blow of 50 ms, dx = 1 cm, Courant 1 (40,000 internal steps):

* Fig. 7: pipe and plug of 100 cells each, plug friction only (the paper's scene);
* every effect: plug friction and soil friction over the penetrated length (tau1 = 20 kPa,
  tau2 = 10 kPa, contact growth).

For each scene it times, alternately in every round and in one process,

(a) the core's path without numba, as a host without numba (or with ``PIPEPLUG_NO_JIT=1``) runs
    it: whole-array numpy steps through two ``advance`` calls;
(b) the numpy-per-step reference of the same scheme (:mod:`.elastic_reference`, which never
    imports the core) on the model's own arrays;

and prints the best seconds of each, the ratio (a)/(b) of the bests (target <= 1.5) with the
range of the rounds' ratios, and the largest field difference of (a) from the compiled loops
(when numba is enabled) and from (b), relative to each field's size.
"""
from __future__ import annotations

import argparse
import sys
import time

from pipeplug import Options, Params, jit
from pipeplug.elastic.model import ElasticModel

from .effects import FULL
from .elastic import disagreement, run_arrays
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


def run_scene(model) -> float:
    """The blow and the rest after it through ``advance``; seconds."""
    from pipeplug_harness.figures.fig7 import Q0, T0, T_END
    start = time.perf_counter()
    model.advance(Q0, T0)
    model.advance(0.0, T_END - T0)
    return time.perf_counter() - start


def compare(changes: dict, growth: bool, reference, repeat: int) -> dict:
    """Timings [s] of (a) and (b), alternating, and the agreement figures of one scene."""
    core_times, ref_times = [], []
    for _ in range(repeat):
        core = elastic_model(changes, growth, vectorised=True)
        core_times.append(run_scene(core))
        ref = elastic_model(changes, growth, vectorised=True)
        ref_times.append(run_arrays(reference, ref))
    res = {"core": min(core_times), "reference": min(ref_times),
           "ratios": [a / b for a, b in zip(core_times, ref_times)],
           "vs_reference": disagreement(core, ref)}
    if jit.enabled():
        compiled = elastic_model(changes, growth, vectorised=False)
        run_scene(compiled)
        res["vs_compiled"] = disagreement(core, compiled)
    return res


def main(argv=None) -> int:
    """Command-line entry point."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed rounds (best kept)")
    args = parser.parse_args(argv)
    print("0.08 s, dx = 1 cm, Courant 1: 40,000 internal steps; best of "
          f"{args.repeat} alternating rounds")
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
