"""Build ``dist/PipePlug.fmu``: ``python build_fmu.py [--dest PATH]`` from the repository root.

A thin entry point to :mod:`pipeplug_fmu.build` (``python -m pipeplug_fmu build`` does the same
from an installed wheel).
"""
from __future__ import annotations

import sys
from pathlib import Path

sys.path[:0] = [str(Path(__file__).resolve().parent / "fmu_src")]   # also without installing

from pipeplug_fmu.build import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
