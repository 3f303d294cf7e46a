"""The command line's contract, as a user meets it from a folder of their own: one line and exit
code 2 for every mistake, the FMUs found without --fmu, temporary folders removed, --version."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from pipeplug_harness import fmus
from pipeplug_harness.errors import UserError

SCENE = ("[pipe]\nL1 = 1.0\n[plug]\nL2 = 1.0\ntau2 = 1e4\n[soil]\ntau1 = 2e4\n"
         "[blows]\namplitude = 23000.0\nduration = 0.05\n[output]\nstop_time = 0.1\n")


def _run(folder: Path, *args, env=None):
    return subprocess.run([sys.executable, "-m", "pipeplug_harness.cli", *map(str, args)],
                          cwd=folder, capture_output=True, text=True, timeout=600, check=False,
                          env={**os.environ, **(env or {})})


def _one_line(proc, code=2, words=()):
    assert proc.returncode == code, proc.stdout + proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    for word in words:
        assert word in lines[0], (word, lines[0])
    return lines[0]


def test_version(tmp_path):
    proc = _run(tmp_path, "--version")
    from pipeplug import __version__
    assert proc.returncode == 0 and proc.stdout.strip() == f"pipeplug {__version__}"


@pytest.mark.parametrize("args, words", [
    (("scene", "missing.toml"), ["missing.toml: no such file"]),
    (("drive", "."), ["is a folder, not a file"]),
    (("sweep", "missing.toml"), ["missing.toml: no such file"]),
    (("system", "--ssp", "missing.ssp"), ["missing.ssp", "no such file"]),
    (("fuzz", "--replay", "missing.json"), ["missing.json", "no such fuzz case file"]),
    (("fuzz", "--jobs", "2"), ["unrecognized arguments: --jobs 2"]),        # Dask only now
    (("fuzz", "--cases", "-3"), ["--cases = -3; allowed: >= 1"]),
    (("scene", "s.toml", "--limit", "speed=3"), ["--limit", "memory, steps"]),
    (("figures", "--only", "8"), ["invalid choice: '8'"]),
    (("stability", "--long-steps", "-1"), ["--long-steps = -1; allowed: >= 1"]),
    (("validate", "--step", "0"), ["--step = 0.0; allowed: > 0 s"]),
    (("nosuch",), ["invalid choice: 'nosuch'"]),
    (("scene", "/dev/zero"), ["/dev/zero: is not a regular file"]),          # never read
    (("fuzz", "--replay", "/dev/zero"), ["not a fuzz case file"]),
    (("fuzz", "--seed", "-1"), ["--seed = -1; allowed: >= 0"]),
    (("validate", "--random", "100000000"), ["--limit memory="]),
    # a file that is not an FMU was counted as a failing fuzz case (exit 1)
    (("fuzz", "--fmu", "s.toml", "--cases", "5"), ["s.toml: not an FMU"]),
    (("scene", "s.toml", "--fmu", "."), [": not an FMU"]),
    (("fuzz", "--paths", "", "--cases", "5"), ["--paths = ''; allowed: python, compiled"]),
    (("fuzz", "--no-fmu", "--fmu", "x.fmu"), ["--fmu = 'x.fmu'; allowed: none with --no-fmu"]),
])
def test_every_mistake_is_one_line_with_exit_code_2(tmp_path, args, words):
    (tmp_path / "s.toml").write_text(SCENE)
    _one_line(_run(tmp_path, *args), 2, words)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]      # nothing written


@pytest.mark.parametrize("command", [("validate",), ("fuzz", "--cases", "5"),
                                     ("scene", "s.toml")])
def test_another_fmu_than_pipeplugs_is_refused_up_front(tmp_path, hammer_file, hammer_dir,
                                                         command):
    """Hammer.fmu as --fmu: validate ended in "internal error: ValueError: no field of name
    v_pipe", fuzz counted its cases as failures and saved them (exit 1)."""
    (tmp_path / "s.toml").write_text(SCENE)
    for fmu in (hammer_file, hammer_dir):
        _one_line(_run(tmp_path, *command, "--fmu", fmu), 2,
                  [str(fmu), "modelName = 'Hammer'; allowed: a PipePlug FMU"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]      # nothing written


def test_an_output_folder_that_is_a_file_or_someone_elses_is_refused(tmp_path, fmu_file):
    (tmp_path / "s.toml").write_text(SCENE)
    (tmp_path / "afile").write_text("mine")
    _one_line(_run(tmp_path, "scene", "s.toml", "--fmu", fmu_file, "--out", "afile"), 2,
              ["--out", "a folder (this is a file)"])
    _one_line(_run(tmp_path, "scene", "s.toml", "--fmu", fmu_file, "--out", "afile/x"), 2,
              ["--out", "a folder that can be created"])
    theirs = tmp_path / "theirs"
    theirs.mkdir()
    (theirs / "s.csv").write_text("their results")
    _one_line(_run(tmp_path, "scene", "s.toml", "--fmu", fmu_file, "--out", "theirs"), 2,
              ["holds other files"])
    assert (theirs / "s.csv").read_text() == "their results"


DRIVE = ("[pipe]\nL1 = 1.0\n[plug]\nL2 = 1.0\ntau2 = 1e4\n[soil]\ntau1 = 2e4\n"
         "[blows]\namplitude = 23000.0\nduration = 0.01\nperiod = 0.015\n"
         "[model]\nelastic = false\n[drive]\nmax_blows = 2\n")


def _contents(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def test_a_folder_of_another_command_is_refused_and_left_as_it_was(tmp_path, fmu_file):
    """A drive into a scene's folder exited 0, replaced the scene's CSV, kept its PNG and
    rewrote the manifest as the drive's."""
    for kind, text in (("scene", SCENE), ("drive", DRIVE)):      # x.csv from either
        (tmp_path / kind).mkdir()
        (tmp_path / kind / "x.toml").write_text(text)
    proc = _run(tmp_path, "scene", "scene/x.toml", "--fmu", fmu_file, "--out", "o")
    assert proc.returncode == 0, proc.stderr
    before = _contents(tmp_path / "o")
    assert {"x.csv", "x.png", "_pipeplug.json"} <= set(before)
    _one_line(_run(tmp_path, "drive", "drive/x.toml", "--fmu", fmu_file, "--out", "o"), 2,
              ["--out = 'o'", "one pipeplug drive wrote", "output of pipeplug scene"])
    assert _contents(tmp_path / "o") == before


def test_a_refused_folder_is_left_exactly_as_it_was(tmp_path, fmu_file):
    """--out . in a folder of the user's files was refused, but .pipeplug.lock stayed there."""
    (tmp_path / "s.toml").write_text(SCENE)
    before = _contents(tmp_path)
    _one_line(_run(tmp_path, "scene", "s.toml", "--fmu", fmu_file, "--out", "."), 2,
              ["--out", "holds other files"])
    assert _contents(tmp_path) == before

def test_without_fmu_the_cached_build_is_used_from_any_folder(tmp_path, fmu_file):
    """dist/PipePlug.fmu relative to the current folder ended in a traceback elsewhere; the
    command now takes the build of its installation from the user's cache, and removes the
    folder it unpacks the FMU into."""
    cache = tmp_path / "cache"
    os.environ["PIPEPLUG_CACHE_DIR"] = str(cache)
    try:
        folder = fmus.cache_root() / "fmu" / fmus.build_digest()
    finally:
        del os.environ["PIPEPLUG_CACHE_DIR"]
    shutil.copytree(fmu_file.parent, folder)
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "s.toml").write_text(SCENE)
    temp = tmp_path / "temp"
    temp.mkdir()
    proc = _run(mine, "scene", "s.toml", env={"PIPEPLUG_CACHE_DIR": str(cache),
                                              "TMPDIR": str(temp)})
    assert proc.returncode == 0, proc.stderr
    assert (mine / "out" / "scenes" / "s.csv").exists()
    assert list(temp.iterdir()) == []                  # the unpacked FMU is gone


def test_a_missing_build_is_built_once_into_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PIPEPLUG_CACHE_DIR", str(tmp_path / "cache"))
    built = []

    def build(folder):
        built.append(folder)
        (folder / "PipePlug.fmu").write_bytes(b"fmu")

    first = fmus.cached_build(build)
    assert first.read_bytes() == b"fmu" and first.parent.name == fmus.build_digest()
    assert fmus.cached_build(build) == first and len(built) == 1
    assert [p.name for p in first.parent.parent.iterdir()] == [first.parent.name]
    with pytest.raises(UserError, match="no such FMU"):
        fmus.find_fmu(tmp_path / "nowhere.fmu")


def test_a_sweep_leaves_nothing_in_the_temporary_directory(tmp_path):
    """Dask's scratch space and lock files stayed behind in the temporary directory."""
    scene = SCENE.replace("[output]\nstop_time = 0.1\n", "").replace("tau1 = 2e4\n", "")
    (tmp_path / "g.toml").write_text(scene + "[model]\nelastic = false\n[grid]\n"
                                             "tau1 = [1e4, 2e4]\n")
    temp = tmp_path / "temp"
    temp.mkdir()
    proc = _run(tmp_path, "sweep", "g.toml", "--workers", "1", "--no-progress",
                env={"TMPDIR": str(temp)})
    assert proc.returncode == 0, proc.stderr
    assert list(temp.iterdir()) == []


def test_a_cache_that_cannot_be_used_is_one_line(tmp_path, monkeypatch):
    """A cache folder that is a file (or another user's) gave an internal PermissionError."""
    blocked = tmp_path / "cache"
    blocked.write_text("not a folder")
    monkeypatch.setenv("PIPEPLUG_CACHE_DIR", str(blocked))
    with pytest.raises(UserError, match="the FMU cache cannot be used.*PIPEPLUG_CACHE_DIR"):
        fmus.cached_build(lambda folder: None)
