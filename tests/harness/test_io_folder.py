"""Output folders never lose data: a file of the folder that its manifest does not name is never
written over."""
import json
import os

import pytest

from pipeplug_harness.errors import UserError
from pipeplug_harness.io import OutputFolder


def test_a_file_the_manifest_does_not_name_is_never_written_over(tmp_path):
    """A user's file put into a folder a pipeplug command wrote (x.csv, then a scene x.toml run
    there) was replaced by the scene's CSV."""
    with OutputFolder(tmp_path / "out", "scene") as out:
        out.file("a.csv").write_text("first run")
    (tmp_path / "out" / "x.csv").write_text("the user's")
    with OutputFolder(tmp_path / "out", "scene") as out:
        out.file("a.csv").write_text("second run")                  # its own: replaced
        with pytest.raises(UserError, match="x.csv"):
            out.file("x.csv")
        assert "x.csv" not in out.data["files"]
    assert (tmp_path / "out" / "x.csv").read_text() == "the user's"
    assert (tmp_path / "out" / "a.csv").read_text() == "second run"


@pytest.mark.parametrize("first, second", [("scene", "drive"), ("scene", "sweep"),
                                           ("sweep", "scene"), ("sweep", "drive")])
def test_a_folder_holding_another_commands_manifest_is_refused_as_it_is(tmp_path, first, second):
    """A drive run into a scene's folder replaced the scene's CSV, kept its PNG and rewrote the
    manifest as the drive's; a scene into a finished sweep's folder broke its dataset."""
    with OutputFolder(tmp_path / "o", first) as out:
        out.file("a.csv").write_text("first")
    before = {p.name: p.read_bytes() for p in (tmp_path / "o").iterdir()}
    with pytest.raises(UserError) as refused:
        OutputFolder(tmp_path / "o", second)
    text = str(refused.value)
    assert str(tmp_path / "o") in text and f"pipeplug {first}" in text, text
    assert f"one pipeplug {second} wrote" in text, text
    assert {p.name: p.read_bytes() for p in (tmp_path / "o").iterdir()} == before
    with OutputFolder(tmp_path / "o", first) as out:             # its own command: accepted
        assert out.data["files"] == ["a.csv"]


def _refuse(_previous):
    raise UserError("refused by the command")


@pytest.mark.parametrize("why", ["other files", "another command", "accept", "bad manifest"])
def test_a_refused_run_leaves_no_lock_file_behind(tmp_path, why):
    """--out . in a folder of the user's files was refused ("holds other files"), but
    .pipeplug.lock stayed there."""
    folder = tmp_path / "o"
    folder.mkdir()
    if why == "other files":
        (folder / "mine.txt").write_text("the user's")
    elif why == "bad manifest":
        (folder / "_pipeplug.json").write_text("{not json")
    else:
        OutputFolder(folder, "scene").release()
        (folder / ".pipeplug.lock").unlink()            # as a folder copied without it
    before = {p.name: p.read_bytes() for p in folder.iterdir()}
    with pytest.raises(UserError):
        OutputFolder(folder, "drive" if why == "another command" else "scene",
                     accept=_refuse if why == "accept" else None)
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == before


def test_a_refused_run_keeps_a_lock_file_it_did_not_make(tmp_path):
    """The lock file of an earlier run is the folder's: a refused run leaves it (and it still
    locks: a run holding it refuses the next)."""
    OutputFolder(tmp_path / "o", "scene").release()
    with pytest.raises(UserError, match="holds the output of pipeplug scene"):
        OutputFolder(tmp_path / "o", "drive")
    assert (tmp_path / "o" / ".pipeplug.lock").exists()
    with OutputFolder(tmp_path / "o", "scene"):
        with pytest.raises(UserError, match="no other pipeplug command is writing into"):
            OutputFolder(tmp_path / "o", "scene")


def test_removing_its_files_removes_the_folders_they_leave_empty_only(tmp_path):
    with OutputFolder(tmp_path / "o", "fuzz") as out:
        for sub in ("a", "b"):
            (tmp_path / "o" / sub).mkdir()
            out.file(f"{sub}/case.json").write_text("{}")
        (tmp_path / "o" / "b" / "mine.txt").write_text("the user's")
        out.remove_owned()
        assert out.data["files"] == []
    assert not (tmp_path / "o" / "a").exists()
    assert (tmp_path / "o" / "b" / "mine.txt").read_text() == "the user's"
    assert not (tmp_path / "o" / "b" / "case.json").exists()


def test_a_manifest_naming_files_outside_its_folder_deletes_none_of_them(tmp_path):
    """A manifest edited by hand (or by another tool) to name "../x", an absolute path or a file
    behind a link out of the folder: removing the run's files leaves those alone."""
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    for name in ("x.txt", "y.txt", "z.txt"):
        (outside / name).write_text("the user's")
    with OutputFolder(tmp_path / "o", "fuzz") as out:
        out.file("mine.csv").write_text("t\n")
    os.symlink(outside, tmp_path / "o" / "link")
    manifest = tmp_path / "o" / "_pipeplug.json"
    data = json.loads(manifest.read_text())
    data["files"] += ["../elsewhere/x.txt", str(outside / "y.txt"), "link/z.txt"]
    manifest.write_text(json.dumps(data))
    with OutputFolder(tmp_path / "o", "fuzz") as out:
        out.remove_owned()
    assert sorted(p.read_text() for p in outside.iterdir()) == ["the user's"] * 3
    assert not (tmp_path / "o" / "mine.csv").exists()
