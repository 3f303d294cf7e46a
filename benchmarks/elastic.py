"""Benchmark of the elastic kernel, and the paper's Fig. 7 claim recomputed.

Run ``python -m benchmarks.elastic`` (``--fine`` adds two finer grids to the
convergence table, ``--repeat R`` sets the number of timed repetitions). It measures, for the
Fig. 7 scene (0.08 s, dx = 1 cm, Courant 1: 40,000 steps of two 100-cell rods):

(a) the package's kernel through ``ElasticModel.advance`` (one call per load level, and with
    0.1 ms communication steps as an FMU host would make them);
(b) the same scheme as numpy operations per time step;
(c) the same scheme as a C loop compiled now with ``cc -O3`` (not part of the package);

prints the ratios, the one-time costs apart (import, compilation on an empty cache, loading
from a warm cache, the C compilation), checks that the three agree, and prints the relative
difference of the peak pipe velocity at x = L1/2 between model I and converged model III.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

_FIELDS = ("v1", "N1", "v2", "N2", "u1", "u2", "acc")
_COLD_PROBE = r"""
import json, time
t = time.perf_counter(); import pipeplug.elastic; t_import = time.perf_counter() - t
from pipeplug import build_model
model = build_model({}, {"elastic": True})
t = time.perf_counter(); model.advance(23000.0, 2e-6); t_first = time.perf_counter() - t
print(json.dumps({"import": t_import, "first_advance": t_first}))
"""


def _one_time_costs() -> dict:
    """Import and first-call times in fresh processes: empty cache, then warm cache [s]."""
    out = {}
    with tempfile.TemporaryDirectory(prefix="pipeplug_cache_") as cache:
        env = dict(os.environ, PIPEPLUG_CACHE_DIR=cache)
        for label in ("cold", "warm"):
            done = subprocess.run([sys.executable, "-c", _COLD_PROBE], env=env, check=True,
                                  capture_output=True, text=True)
            out[label] = json.loads(done.stdout.strip().splitlines()[-1])
    return out


def _fresh_model(dx: float = 0.01):
    from pipeplug import build_model
    return build_model({"dx": dx}, {"elastic": True})


def scene_steps(model):
    """(steps, dt, Q) of the two load levels of the Fig. 7 scene (one blow, then rest)."""
    from pipeplug_harness.figures.fig7 import Q0, T0, T_END
    plan = []
    for q, h in ((Q0, T0), (0.0, T_END - T0)):
        n = model.steps_for(h)
        plan.append((n, h / n, q))
    return plan


def run_arrays(runner, model) -> float:
    """Run ``runner`` (kernel signature) over the scene on ``model``'s arrays; seconds."""
    g = model.grid
    start = time.perf_counter()
    for n, dt, q in scene_steps(model):
        runner(n, dt, q, g.coef, model.v1, model.N1, model.v2, model.N2, g.cells1, model.u1,
               g.cells2, model.u2, model.acc)
    return time.perf_counter() - start


def _time_model(repeat: int, h: float | None) -> tuple[float, object]:
    """Best wall time of the scene through ``advance`` (h None: one call per load level)."""
    from pipeplug_harness.figures.fig7 import Q0, T0, T_END
    best, model = np.inf, None
    for _ in range(repeat):
        model = _fresh_model()
        start = time.perf_counter()
        if h is None:
            model.advance(Q0, T0)
            model.advance(0.0, T_END - T0)
        else:
            for i in range(round(T_END / h)):
                model.advance(Q0 if i < round(T0 / h) else 0.0, h)
        best = min(best, time.perf_counter() - start)
    return best, model


def disagreement(a, b) -> float:
    """Largest difference between two models' fields, relative to each field's size."""
    worst = 0.0
    for name in _FIELDS:
        x, y = getattr(a, name), getattr(b, name)
        scale = max(np.abs(x).max(initial=0.0), 1e-300)
        worst = max(worst, np.abs(x - y).max(initial=0.0) / scale)
    return worst


def timings(repeat: int = 5, with_c: bool = True) -> dict:
    """All timings and agreement figures (see the module docstring)."""
    t = time.perf_counter()
    import pipeplug.elastic  # noqa: F401  (the import itself is measured)
    res = {"import_in_process": time.perf_counter() - t}
    first = _fresh_model()
    res["first_run"] = run_arrays(first._kernel, first)  # compile or cache load + one run
    res["kernel"], ours = _time_model(repeat, None)
    res["kernel_fmu_steps"], _ = _time_model(repeat, 1e-4)
    from .elastic_reference import build_c, run_c, run_numpy
    reference = _fresh_model()
    res["numpy"] = run_arrays(run_numpy, reference)
    res["numpy_vs_kernel"] = disagreement(ours, reference)
    if with_c:
        t = time.perf_counter()
        function = build_c()
        res["c_compile"] = time.perf_counter() - t
        res["c"] = np.inf
        for _ in range(repeat):
            compiled = _fresh_model()
            res["c"] = min(res["c"], run_arrays(
                lambda *args: run_c(function, *args), compiled))
        res["c_vs_kernel"] = disagreement(ours, compiled)
    res["one_time"] = _one_time_costs()
    return res


def _print_timings(res: dict) -> None:
    print("Fig. 7 scene, dx = 1 cm, Courant 1: 40,000 steps of pipe (100 cells) + plug (100)")
    print(f"  (a) kernel, 2 advance calls      {res['kernel'] * 1e3:9.2f} ms")
    print(f"      kernel, 800 calls of 0.1 ms  {res['kernel_fmu_steps'] * 1e3:9.2f} ms")
    print(f"  (b) numpy per time step          {res['numpy'] * 1e3:9.2f} ms"
          f"   -> kernel is {res['numpy'] / res['kernel']:.0f}x faster (target >= 30x)")
    if "c" in res:
        print(f"  (c) C loop, cc -O3               {res['c'] * 1e3:9.2f} ms"
              f"   -> kernel / C = {res['kernel'] / res['c']:.2f} (target <= 3)")
        print(f"  agreement: numpy {res['numpy_vs_kernel']:.1e}, C {res['c_vs_kernel']:.1e}"
              " (largest field difference / field size)")
    else:
        print(f"  agreement: numpy {res['numpy_vs_kernel']:.1e}")
    print("one-time costs (apart):")
    print(f"  import pipeplug.elastic (this process)   {res['import_in_process'] * 1e3:8.1f} ms")
    print(f"  first run here (compile or cache load)   {res['first_run'] * 1e3:8.1f} ms")
    for label, costs in res["one_time"].items():
        print(f"  fresh process, {label} cache: import {costs['import'] * 1e3:7.1f} ms, "
              f"first advance {costs['first_advance'] * 1e3:8.1f} ms")
    if "c_compile" in res:
        print(f"  C compilation                            {res['c_compile'] * 1e3:8.1f} ms")


def _print_fig7(fine: bool) -> None:
    from pipeplug_harness.figures.fig7 import convergence, rigid_peak
    dxs = (0.04, 0.02, 0.01, 0.005, 0.0025) + ((0.00125, 0.000625) if fine else ())
    rows = convergence(dxs)
    print("Fig. 7: pipe velocity at x = L1/2, sampled every 8 us, against the finest grid")
    print("     dx [m]     peak [m/s]   peak diff   RMS diff / peak   model I vs III")
    for r in rows:
        print(f"  {r['dx']:9.6f}  {r['peak']:13.8f}  {r['peak_rel']:10.2e}  {r['rms_rel']:15.2e}"
              f"  {r['rigid_rel'] * 100:13.4f} %")
    print(f"  model I peak (closed form) {rigid_peak():.8f} m/s; paper: difference < 0.25 %")


def main(argv=None) -> int:
    """Command-line entry point."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed repetitions (best kept)")
    parser.add_argument("--fine", action="store_true", help="add dx = 1.25 and 0.625 mm")
    parser.add_argument("--no-c", action="store_true", help="skip the C comparison")
    args = parser.parse_args(argv)
    _print_timings(timings(args.repeat, not args.no_c))
    _print_fig7(args.fine)
    return 0


if __name__ == "__main__":
    sys.exit(main())
