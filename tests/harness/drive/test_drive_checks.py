"""Drives that cannot report garbage: the per-blow checks, the default grid, and the drives
that diverged or created energy before (now finishing with closed ledgers)."""
from __future__ import annotations

import math
from pathlib import Path

import pytest
from drive_helpers import toml_text

from pipeplug import OUTPUTS, Outputs
from pipeplug_harness.drive.checks import DriveInvalid, Limits, check_blow
from pipeplug_harness.drive.file import GRID_CELLS, grid_for, load_drive
from pipeplug_harness.drive.run import Blow, drive_with, run_drive_on_core
from pipeplug_harness.errors import UserError
from pipeplug_harness.session import CoreSession

CASING = Path(__file__).resolve().parents[3] / "scenes" / "drives" / "casing_24in_17m.toml"


def _casing(tmp_path, **changes):
    """The shipped casing drive with some lines changed (``key = value`` by key)."""
    lines = []
    for line in CASING.read_text().splitlines():
        key = line.split("=")[0].strip()
        lines.append(f"{key} = {changes.pop(key)}" if key in changes else line)
    path = tmp_path / "casing.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_drive_without_a_plug_reaches_the_target_with_every_ledger_closed(tmp_path):
    """The casing drive with L2 = 0 diverged at Courant 1 (blow 7 peaked at 1.7e6 m/s and the
    drive reported "refusal at penetration -27.4 m"); now every blow passes the checks and
    the pipe goes in by about 420 blows (430 at Courant 0.9 and 458 at 0.5 before)."""
    result = run_drive_on_core(load_drive(_casing(tmp_path, L2="0.0")))
    assert result.outcome == "target"
    assert 380 <= len(result.blows) <= 460
    assert all(b.set >= 0.0 for b in result.blows)
    assert sum(b.W_friction_outer for b in result.blows) <= sum(b.W_input for b in result.blows)


class _Session(CoreSession):
    """A core session whose readings a defect alters."""

    def __init__(self, start_values, change):
        super().__init__(start_values)
        self.change = change

    def step(self, t, h, q):
        return self.change(super().step(t, h, q), t)


@pytest.mark.parametrize("change, words", [
    (lambda r, t: r._replace(W_friction_outer=r.W_friction_outer * 1.01 + 1.0),
     "energy ledger does not close"),
    (lambda r, t: r._replace(v_pipe=r.v_pipe + (1e4 if t > 0.35 else 0.0)),
     "pipe velocity"),
    (lambda r, t: r._replace(u_pipe=r.u_pipe - (5.0 if t > 0.35 else 0.0)),
     "below the pipe's elastic rebound"),
])
def test_a_blow_that_breaks_physics_stops_the_drive(tmp_path, change, words):
    spec = load_drive(_casing(tmp_path, L2="0.0", max_blows="3"))
    with pytest.raises(DriveInvalid, match=r"^blow \d+: .*" + words):
        drive_with(spec, _Session(spec.start_values, change))


def test_the_check_names_the_blow_and_the_numbers(tmp_path):
    spec = load_drive(_casing(tmp_path))
    limits = Limits.of(spec)
    blow = Blow(7, 1.8, 0.01, 0.5, 3.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, "rest", 0.1, 10, 0.0,
                -1e6, 0.0, -1e6, 0.0, 1.0, math.nan, False, 1.0, 0.0, 2.0, "plugged", 120.0,
                {})
    created = Outputs(*(0.0 for _ in OUTPUTS))._replace(u_pipe=0.5, W_input=7.787e6,
                                                        W_friction_outer=7.889e6, at_rest=True)
    with pytest.raises(DriveInvalid) as info:
        check_blow(limits, blow, created, 2.1, 1000)
    text = str(info.value)
    assert text.startswith("blow 7: ") and "W_input = 7.787e+06 J" in text
    assert "W_friction = 7.889e+06 J" in text


def test_without_dx_the_grid_has_20_cells_along_the_pipe_and_the_blows_wave(tmp_path):
    spec = load_drive(_casing(tmp_path))
    assert "dx given" in spec.grid
    path = tmp_path / "no_dx.toml"
    path.write_text("\n".join(line for line in CASING.read_text().splitlines()
                              if not line.startswith("dx")) + "\n")
    spec = load_drive(path)
    p = spec.params()
    wave = p.c1 * spec.duration                   # 5.05 m: the blow's wave
    n = math.ceil(GRID_CELLS * p.L1 / wave)       # 68 cells of 0.25 m
    assert spec.start_values["dx"] == pytest.approx(p.L1 / n) and n == 68
    assert "68 pipe cells and 68 plug cells" in spec.grid and "dx chosen" in spec.grid


def test_the_default_grid_fits_the_plug_or_asks_for_dx(tmp_path):
    base = {"pipe": {"L1": 10.0}, "plug": {"L2": 2.5, "tau2": 1e4}, "soil": {"tau1": 1e4},
            "blows": {"amplitude": 1e6, "duration": 1e-3, "period": 0.3},
            "model": {"elastic": True}}
    path = tmp_path / "d.toml"
    path.write_text(toml_text(base))
    spec = load_drive(path)
    cells = round(10.0 / spec.start_values["dx"])
    assert cells >= 40 and (cells * 2.5 / 10.0) == round(cells * 2.5 / 10.0)
    p = spec.params()
    with pytest.raises(UserError, match="give dx"):
        grid_for(p.with_(L2=10.0 / math.pi), 1e-3)


@pytest.mark.parametrize("amplitude", ["-2.2133e6", "0.0"])
def test_a_blow_must_push(tmp_path, amplitude):
    with pytest.raises(UserError, match=r"amplitude = .* allowed: > 0"):
        load_drive(_casing(tmp_path, amplitude=amplitude))
