"""Benchmark of whole drives through the FMU: 1,000 blows, rigid and elastic.

Usage::

    python -m benchmarks.drive [--fmu dist/PipePlug.fmu] [--blows 1000] [--repeat 3]
                                           [--only rigid elastic]

Both drives are the shipped scene ``scenes/drives/casing_24in_17m.toml`` (a 24-in casing, 1 ms
blows of 2.2 MN at 200 blows/min) run for exactly ``--blows`` blows (no set refusal):

* rigid: the scene with ``elastic = false`` (target <= 10 s for 1,000 blows);
* elastic: the scene with a 20 m pipe and plug at dx = 5 cm (target <= 60 s for 1,000 blows).

Each drive is timed from the FMU's instantiation to the last blow, after a two-blow warm-up
(imports, compiled-kernel cache) in the same process; ``--repeat`` runs give a range on a shared
machine. Printed per run: wall time, communication steps, how each blow's motion ended (rest:
``at_rest``, so the FMU skipped to the next blow at no cost; front: the front end stood still while
waves rang on in the free part; moving: still moving at the next blow), and for the elastic drive
the internal steps the FMU had to take (blows x period / internal step), the time per cell and
internal step, how many of the internal steps fell while the front end still moved (the
cost of the drive if the rest of each window were skipped as at rest), and the friction work
dissipated after the front end had stopped (``ringing_friction`` of the blows): where it is not 0,
contacts still slipped in the ringing, so the rest of the window is no lossless vibration whose
course could be skipped exactly.
"""
from __future__ import annotations

import argparse
import time
from collections import Counter
from pathlib import Path

from pipeplug.elastic.grid import build_grid
from pipeplug_harness import spec as files
from pipeplug_harness.drive.file import DriveSpec, drive_spec
from pipeplug_harness.drive.run import run_drive
from pipeplug_harness.fmus import find_fmu

SCENE = Path(__file__).resolve().parents[1] / "scenes" / "drives" / "casing_24in_17m.toml"
TARGETS = {"rigid": 10.0, "elastic": 60.0}        #: seconds for 1,000 blows


def spec_for(case: str, blows: int) -> DriveSpec:
    """The benchmark drive ``case`` ("rigid" or "elastic") of ``blows`` blows."""
    values = files.read_file(SCENE, files.DRIVE)
    values["drive"].update(max_blows=blows, refusal_set=0.0)
    if case == "rigid":
        values["elastic"] = False
    else:
        values.update(elastic=True, L1=20.0, L2=20.0, dx=0.05)
        values["drive"]["target"] = 20.0
    return drive_spec(f"{case}", values)


def timed(spec: DriveSpec, fmu: Path) -> tuple[float, object]:
    start = time.perf_counter()
    result = run_drive(spec, fmu)
    return time.perf_counter() - start, result


def report(case: str, seconds: float, result) -> str:
    spec = result.spec
    ends = Counter(b.settled for b in result.blows)
    line = (f"{case:8s} {seconds:7.2f} s  {len(result.blows)} blows ({result.outcome}), "
            f"{result.steps} communication steps, penetration {result.penetration:.4g} m; "
            f"motion ended: rest {ends['rest']}, front {ends['front']}, moving {ends['moving']}")
    if spec.elastic:
        p = spec.params()
        grid = build_grid(p)
        internal = len(result.blows) * spec.period / grid.h_max
        moving = sum(b.motion for b in result.blows) / grid.h_max
        cells = grid.n1 + grid.n2
        line += (f"\n         ~{internal / 1e6:.3g} M internal steps of {cells} cells: "
                 f"{seconds / (internal * cells) * 1e9:.3g} ns per cell and step (all costs); "
                 f"{moving / 1e6:.3g} M of them while the front end moved (mean "
                 f"{1e3 * moving * grid.h_max / len(result.blows):.3g} ms per blow)")
        ringing = [b.ringing_friction for b in result.blows]
        line += (f"\n         friction work after the front end stopped: {sum(ringing):.3g} J, "
                 f"> 0 in {sum(w > 0.0 for w in ringing)} of {len(ringing)} blows")
    return line


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", type=Path, help="the FMU (default: the build of this "
                                                 "installation, made once into the cache)")
    parser.add_argument("--blows", type=int, default=1000, help="blows per drive (%(default)s)")
    parser.add_argument("--repeat", type=int, default=1, help="timed runs per case")
    parser.add_argument("--only", nargs="+", choices=tuple(TARGETS), default=list(TARGETS))
    args = parser.parse_args(argv)
    args.fmu = find_fmu(args.fmu)
    for case in args.only:
        run_drive(spec_for(case, 2), args.fmu)                 # warm-up
        times = []
        for _ in range(args.repeat):
            seconds, result = timed(spec_for(case, args.blows), args.fmu)
            times.append(seconds)
            print(report(case, seconds, result), flush=True)
        target = TARGETS[case] * args.blows / 1000.0
        verdict = "met" if max(times) <= target else ("met in some runs" if min(times) <= target
                                                      else "NOT met")
        print(f"{case}: {min(times):.2f}-{max(times):.2f} s over {len(times)} run(s) for "
              f"{args.blows} blows; target <= {target:g} s: {verdict}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
