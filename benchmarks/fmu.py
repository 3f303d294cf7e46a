"""Cost of one communication step of PipePlug.fmu against the cheapest pythonfmu FMU.

Usage::

    python -m benchmarks.fmu [--fmu dist/PipePlug.fmu] [--steps 2000] [--repeat 7]

Both FMUs are driven in one process through FMPy's raw ``FMU2Slave`` API, one communication step
being ``setReal(Q)``, ``doStep``, ``getReal`` of ``v_pipe v_plug u_pipe u_plug``. The baseline is
a pythonfmu FMU with the same interface whose ``do_step`` does nothing, built into a temporary
directory under a unique module name (pythonfmu FMUs share one interpreter and ``sys.modules``).
The load is the paper's rectangular pulse (Q0 = 23 kN for t0 = 50 ms, then 0) on a 0.1 ms grid,
so PipePlug's steps include its friction events. Rounds alternate between the FMUs; the fastest
round of each is reported (the least disturbed by the rest of the machine). Prints microseconds
per step and their ratio (target for the exact rigid model: <= 1.5).
"""
from __future__ import annotations

import argparse
import tempfile
import time
import uuid
from pathlib import Path

from pipeplug_harness.fmus import find_fmu

OUTPUTS = ("v_pipe", "v_plug", "u_pipe", "u_plug")

_BASELINE = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Real


class {cls}(Fmi2Slave):
    """The cheapest FMU with PipePlug's interface: do_step does nothing."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.Q = 0.0
        self.register_variable(Real("Q", causality=Fmi2Causality.input))
        for name in {outputs!r}:
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=Fmi2Causality.output))

    def do_step(self, current_time, step_size):
        return True
'''


def build_baseline(directory: Path) -> Path:
    """Build the do-nothing FMU into ``directory`` under a unique module and class name."""
    from pythonfmu import FmuBuilder

    tag = uuid.uuid4().hex[:12]
    script = directory / f"bench_baseline_{tag}.py"
    script.write_text(_BASELINE.format(cls=f"BenchBaseline{tag}", outputs=OUTPUTS))
    return Path(FmuBuilder.build_FMU(script, dest=directory))


def pulse(t: float, q0: float = 23e3, t0: float = 0.05) -> float:
    """The rectangular pulse [N] at time ``t`` [s]."""
    return q0 if t < t0 else 0.0


class Driven:
    """One FMU, instantiated through FMPy's raw FMU2Slave API."""

    def __init__(self, fmu: Path, name: str):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        md = read_model_description(str(fmu))
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu)),
                               modelIdentifier=md.coSimulation.modelIdentifier,
                               instanceName=name)
        self.slave.instantiate()

    def run(self, steps: int, h: float, params: dict | None = None) -> float:
        """Seconds per communication step over ``steps`` steps of ``h`` [s] from t = 0, with
        the Real ``params`` set in initialization mode."""
        s = self.slave
        s.reset()
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        for name, value in (params or {}).items():
            s.setReal([self.vr[name]], [value])
        s.exitInitializationMode()
        q_vr, out_vrs = [self.vr["Q"]], [self.vr[n] for n in OUTPUTS]
        loads = [[pulse(k * h)] for k in range(steps)]
        set_real, do_step, get_real = s.setReal, s.doStep, s.getReal
        start = time.perf_counter()
        for k in range(steps):
            set_real(q_vr, loads[k])
            do_step(k * h, h)
            get_real(out_vrs)
        return (time.perf_counter() - start) / steps


def measure(fmu: Path, steps: int, rounds: int, params: dict,
            h: float = 1e-4) -> tuple[float, float]:
    """Best seconds per step of (PipePlug with ``params``, baseline), rounds interleaved."""
    with tempfile.TemporaryDirectory(prefix="pipeplug_bench_") as tmp:
        baseline = Driven(build_baseline(Path(tmp)), "baseline")
        model = Driven(fmu, "pipeplug")
        model.run(steps, h, params)               # warm-up: imports, caches
        baseline.run(steps, h)
        best_model, best_base = float("inf"), float("inf")
        for _ in range(rounds):
            best_model = min(best_model, model.run(steps, h, params))
            best_base = min(best_base, baseline.run(steps, h))
        for driven in (model, baseline):
            driven.slave.terminate()
            driven.slave.freeInstance()
    return best_model, best_base


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", type=Path, default=None,
                        help="the FMU to measure (default: the build of this installation)")
    parser.add_argument("--steps", type=int, default=2000, help="steps per round (h = 0.1 ms)")
    parser.add_argument("--repeat", type=int, default=7, help="rounds per FMU")
    parser.add_argument("--tau1", type=float, default=None, help="outer limit stress [Pa]")
    parser.add_argument("--tau2", type=float, default=None, help="inner limit stress [Pa]")
    args = parser.parse_args(argv)
    args.fmu = find_fmu(args.fmu)
    params = {k: v for k, v in (("tau1", args.tau1), ("tau2", args.tau2)) if v is not None}
    t_model, t_base = measure(args.fmu, args.steps, args.repeat, params)
    label = ", ".join(f"{k}={v:g}" for k, v in params.items()) or "defaults"
    rows = ((f"PipePlug (exact rigid, {label})", t_model), ("do-nothing pythonfmu baseline", t_base))
    width = max(len(name) for name, _ in rows) + 1
    for name, seconds in rows:
        print(f"{name + ':':<{width}} {seconds * 1e6:8.2f} us per step")
    print(f"ratio: {t_model / t_base:.2f}  (target <= 1.5)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
