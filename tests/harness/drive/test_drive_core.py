"""The drive loop on a core model (what sweeps run) gives what it gives through the FMU, bit for
bit: the FMU wraps the same model and steps it the same way."""
from dataclasses import asdict

import pytest
from drive_helpers import toml_text

from pipeplug_harness.drive.file import load_drive
from pipeplug_harness.drive.run import run_drive_on_core

DRIVES = {
    # blows that end with the pipe still moving, the plug sliding both ways, then a static
    # refusal (the MOVING case of test_drive_rigid)
    "rigid": {"plug": {"tau2": 3.0e4}, "soil": {"tau1": 2.0e5},
              "blows": {"amplitude": 1.5e4, "duration": 0.01, "period": 0.015},
              "model": {"elastic": False}, "drive": {"refusal_set": 0.0, "max_blows": 6}},
    # the elastic model: waves ringing in the free part, a coarse grid
    "elastic": {"pipe": {"L1": 2.0}, "plug": {"L2": 1.0, "tau2": 3.0e4},
                "soil": {"tau1": 1.0e5}, "model": {"elastic": True, "dx": 0.1},
                "blows": {"amplitude": 5.0e4, "duration": 0.002, "period": 0.01},
                "drive": {"max_blows": 3}},
    # a hammer: strikes of a ram through a cushion on the elastic pipe
    "hammer": {"pipe": {"L1": 2.0}, "plug": {"L2": 1.0, "tau2": 3.0e4},
               "soil": {"tau1": 1.0e5}, "model": {"elastic": True, "dx": 0.1},
               "hammer": {"rated_energy": 2000.0, "efficiency": 0.8, "ram_mass": 100.0,
                          "rate": 20.0, "cushion_stiffness": 5e8,
                          "cushion_restitution": 0.8},
               "drive": {"max_blows": 3}},
}


def _same(a, b) -> bool:
    """Equal records, a NaN equal to a NaN (enthru_share without a hammer)."""
    return all(x == y or (x != x and y != y) for x, y in zip(a.values(), b.values())) \
        and a.keys() == b.keys()


@pytest.mark.parametrize("name", DRIVES)
def test_core_session_drive_equals_the_fmu_drive(run_drive, tmp_path, name):
    fmu = run_drive(DRIVES[name])
    path = tmp_path / "core.toml"
    path.write_text(toml_text(DRIVES[name]))
    core = run_drive_on_core(load_drive(path))
    assert (core.outcome, core.steps) == (fmu["outcome"], fmu["steps"])
    assert len(core.blows) == len(fmu["blows"])
    assert all(_same(asdict(a), b) for a, b in zip(core.blows, fmu["blows"]))
