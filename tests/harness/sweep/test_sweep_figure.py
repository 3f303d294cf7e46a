"""Where ``pipeplug sweep`` draws its report's figure: by default in its output folder under the
manifest (never over a file it did not write), or at ``--figure``, checked before the run."""
import json

import pyarrow.parquet as pq

# Four short rigid drives (~3 ms each) over a grid of the outer friction.
DRIVES = """
[sweep]
kind = "drive"
chunk = 2
report = "drivability"
[grid]
tau1 = [6.0e4, 7.0e4, 8.0e4, 9.0e4]
[pipe]
L1 = 2.0
[plug]
L2 = 2.0
tau2 = 2.0e4
[blows]
amplitude = 23000.0
duration = 0.01
period = 0.2
[model]
elastic = false
[drive]
target = 1.0
step = 0.01
"""


def _one_line(proc, words):
    assert proc.returncode == 2, proc.stdout + proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for word in words:
        assert word in lines[0], (word, lines[0])


def test_the_default_figure_goes_into_the_output_folder_not_over_a_users_file(
        pipeplug_cli, tmp_path):
    """With --out res the figure went to out/sweeps/drives.png, a path outside --out, over the
    user's file there."""
    (tmp_path / "drives.toml").write_text(DRIVES)
    (tmp_path / "out" / "sweeps").mkdir(parents=True)
    (tmp_path / "out" / "sweeps" / "drives.png").write_text("the user's")
    for _ in range(2):                                    # a rerun replaces its own figure
        proc = pipeplug_cli("sweep", "drives.toml", "--out", "res", "--workers", 1,
                            "--no-progress")
        assert f"wrote {tmp_path / 'res' / '_drivability.png'}" in proc.stdout, proc.stdout
    assert (tmp_path / "out" / "sweeps" / "drives.png").read_text() == "the user's"
    assert sorted(p.name for p in (tmp_path / "out" / "sweeps").iterdir()) == ["drives.png"]
    assert (tmp_path / "res" / "_drivability.png").read_bytes()[:4] == b"\x89PNG"
    manifest = json.loads((tmp_path / "res" / "_pipeplug.json").read_text())
    assert manifest["files"] == ["_drivability.png"] and manifest["command"] == "sweep"
    assert pq.read_table(tmp_path / "res").num_rows == 4        # still one Parquet dataset


def test_a_figure_that_cannot_be_written_is_refused_before_the_run(pipeplug_cli, tmp_path):
    """--figure drives.toml/x.png ran the whole sweep, then ended in "internal error:
    FileExistsError", exit 1."""
    (tmp_path / "drives.toml").write_text(DRIVES)
    _one_line(pipeplug_cli("sweep", "drives.toml", "--out", "a", "--figure", "drives.toml/x.png",
                           check=False),
              ["--figure = 'drives.toml/x.png'", "drives.toml is a file"])
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "_drivability.png").write_text("the user's")
    _one_line(pipeplug_cli("sweep", "drives.toml", "--out", "b", check=False),
              ["--out = 'b'", "_drivability.png", "not one _pipeplug.json names"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b", "drives.toml"]  # no run began
    assert [p.name for p in (tmp_path / "b").iterdir()] == ["_drivability.png"]


def test_a_figure_path_over_data_a_users_file_or_another_output_is_refused(pipeplug_cli,
                                                                          tmp_path):
    """--figure over the sweep's own Parquet part, over a user's text file or over a scene's
    figure (named in its folder's manifest) wrote a PNG there, exit 0: the campaign's data was
    lost, its next run ended in "internal error: ArrowInvalid". Now each is one line, exit 2,
    and nothing is written; a PNG of the user's own at a free path is still the figure."""
    (tmp_path / "drives.toml").write_text(DRIVES)
    pipeplug_cli("sweep", "drives.toml", "--out", "d", "--workers", 1, "--no-progress")
    part = next((tmp_path / "d").glob("*.parquet"))
    data = part.read_bytes()
    (tmp_path / "notes.txt").write_text("mine")
    (tmp_path / "scene").mkdir()
    (tmp_path / "scene" / "fig.png").write_bytes(b"\x89PNG\r\n\x1a\n a scene's")
    (tmp_path / "scene" / "_pipeplug.json").write_text(json.dumps(
        {"command": "scene", "files": ["fig.png"]}))
    for figure, words in ((part, ["a path ending in .png"]),
                          (tmp_path / "notes.txt", ["a path ending in .png"]),
                          (tmp_path / "scene" / "fig.png", ["another output's file"])):
        _one_line(pipeplug_cli("sweep", "drives.toml", "--out", "d", "--figure", figure,
                               "--workers", 1, check=False), [f"--figure = '{figure}'", *words])
    (tmp_path / "old.png").write_text("not a PNG")
    _one_line(pipeplug_cli("sweep", "drives.toml", "--out", "d", "--figure", "old.png",
                           check=False), ["--figure = 'old.png'", "not a PNG"])
    assert part.read_bytes() == data and (tmp_path / "notes.txt").read_text() == "mine"
    assert (tmp_path / "scene" / "fig.png").read_bytes().endswith(b"a scene's")
    proc = pipeplug_cli("sweep", "drives.toml", "--out", "d", "--figure", "mine.png",
                        "--workers", 1, "--no-progress")
    assert (tmp_path / "mine.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", proc.stdout


def test_a_worker_count_below_one_is_refused(pipeplug_cli, tmp_path):
    """--workers -1 hung with no output (a LocalCluster of no worker), its folder made."""
    (tmp_path / "drives.toml").write_text(DRIVES)
    for workers in (0, -1):
        _one_line(pipeplug_cli("sweep", "drives.toml", "--out", "w", "--workers", workers,
                               check=False), [f"--workers = {workers}", ">= 1"])
    assert not (tmp_path / "w").exists()


def test_a_report_that_does_not_fit_the_sweep_is_refused_before_the_run(pipeplug_cli,
                                                                        tmp_path):
    """report = "domains" on drives ran every case, then ended in "internal error:
    ValueError", exit 1, with the results on disk and a figure never drawn."""
    (tmp_path / "domains.toml").write_text(DRIVES.replace('report = "drivability"',
                                                          'report = "domains"'))
    _one_line(pipeplug_cli("sweep", "domains.toml", "--out", "r", "--workers", 1,
                           check=False),
              ["report = 'domains'", 'single blows (kind = "blow", count = 1)',
               "a [grid] over tau1 and tau2 only", "domains.toml"])
    assert not (tmp_path / "r").exists()
