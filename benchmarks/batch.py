"""Throughput of the core's batch API: single blows, cases per second on one core.

Usage (from the repository root)::

    python -m benchmarks.batch [--cases 20000] [--repeat 5] [--seed 1]

What is measured: :mod:`pipeplug_harness.cost.batch` (the cost study measures it too).
"""
from __future__ import annotations

import argparse

from pipeplug_harness.cost.batch import TARGET, throughput


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=20_000, help="cases per run")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs (best reported)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the parameter draw")
    args = parser.parse_args(argv)
    res = throughput(args.cases, args.repeat, args.seed)
    path = "compiled (numba)" if res["compiled"] else "plain Python (numba not available)"
    print(f"batch API, {res['cases']} single blows, {path}: {res['rate']:,.0f} cases/s on one "
          f"core (target >= {TARGET:,}); {res['at_rest']:.1%} of the cases came to rest")
    print(f"batch API as plain Python:              {res['rate_python']:,.0f} cases/s")
    print(f"build_model + advance, one by one:      {res['rate_one_by_one']:,.0f} cases/s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
