"""``python -m pipeplug_fmu build [--dest DIR]``: build the FMUs (see :mod:`pipeplug_fmu.build`)."""
from __future__ import annotations

import sys

from .build import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
