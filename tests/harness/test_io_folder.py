"""Output folders never lose data: a file of the folder that its manifest does not name is never
written over."""
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
