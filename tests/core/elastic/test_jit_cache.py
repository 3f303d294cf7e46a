"""The compiled kernels are reused by a new process even when the sources moved.

An FMU importer unpacks the FMU's files into a fresh folder for each run; numba's own cache is
keyed by that folder. The package keys it by the sources' content instead.
"""
from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import pipeplug

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(importlib.util.find_spec("numba") is None,
                                 reason="numba is not installed")]

_PROBE = r"""
import json
import pipeplug
from pipeplug import build_model
model = build_model({"tau2": 0.0, "dx": 0.1}, {"elastic": True})
model.advance(1000.0, 1e-4)
stats = model._kernel.stats
print(json.dumps({"file": pipeplug.__file__, "hits": sum(stats.cache_hits.values()),
                  "misses": sum(stats.cache_misses.values()), "path": stats.cache_path}))
"""


def _run_copy(tmp_path: Path, folder: str, cache: Path) -> dict:
    """Copy the package into ``tmp_path/folder`` and run the probe from there."""
    root = tmp_path / folder
    shutil.copytree(Path(pipeplug.__file__).parent, root / "pipeplug",
                    ignore=shutil.ignore_patterns("__pycache__"))
    env = dict(os.environ, PIPEPLUG_CACHE_DIR=str(cache), PYTHONPATH=str(root))
    env.pop("PIPEPLUG_NO_JIT", None)
    done = subprocess.run([sys.executable, "-c", _PROBE], env=env, cwd=root, check=True,
                          capture_output=True, text=True)
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert Path(result["file"]).is_relative_to(root)  # the copy was imported
    return result


def test_compiled_kernel_is_reused_after_the_sources_move(tmp_path):
    cache = tmp_path / "cache"
    first = _run_copy(tmp_path, "unpacked_1", cache)
    second = _run_copy(tmp_path, "unpacked_2", cache)
    assert (first["hits"], first["misses"]) == (0, 1)
    assert (second["hits"], second["misses"]) == (1, 0)
    assert Path(first["path"]).is_relative_to(cache) and first["path"] == second["path"]
