"""The output folder without a cluster: a worker writes its chunk only where it sees the client's
folder (this run's token), the file is the bytes the client would write, and a writer killed
mid-write leaves no chunk."""
import subprocess
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from pipeplug_harness.errors import RunFailed, UserError
from pipeplug_harness.io import MANIFEST, OutputFolder, parquet_bytes
from pipeplug_harness.sweep.engine import _run_stored
from pipeplug_harness.sweep.store import ChunkFiles, ChunkStore, Written, read_folder


class Tiny:
    """A campaign of 3 chunks of 4 rows (a text column too)."""

    name, n_chunks, digest = "tiny", 3, "tiny-1"

    def chunk_cases(self, c):
        return 4

    def run_chunk(self, c):
        cases = list(range(4 * c, 4 * c + 4))
        return pa.table({"case": pa.array(cases, pa.int64()),
                         "x": [k / 7 for k in cases], "error": [""] * 4})


def test_a_worker_that_sees_the_folder_writes_the_clients_bytes(tmp_path):
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    ack = _run_stored(Tiny(), 1, store.files)
    assert ack == Written(1, 4) and store.done(1) and not store.done(0)
    assert store.path(1).read_bytes() == parquet_bytes(Tiny().run_chunk(1))
    assert sorted(p.name for p in store.folder.iterdir()) == [".pipeplug.lock", MANIFEST,
                                                              "part-000001.parquet"]


def test_a_worker_that_does_not_see_it_sends_the_bytes(tmp_path):
    """A same-named folder elsewhere (another run's token) or none at all: nothing written."""
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    elsewhere = ChunkFiles(store.folder, store.files.width, "another-run")
    nowhere = ChunkFiles(tmp_path / "absent", store.files.width, store.files.token)
    for files in (elsewhere, nowhere, None):
        data = _run_stored(Tiny(), 2, files)
        assert data == parquet_bytes(Tiny().run_chunk(2))
    assert not store.parts() and not (tmp_path / "absent").exists()
    store.write(2, data)
    assert store.done(2) and store.path(2).read_bytes() == data


def test_a_writer_killed_mid_write_leaves_no_chunk(tmp_path):
    """A process killed (SIGKILL) with chunk 1's file written but not yet renamed: the folder
    shows chunk 0 only, to any Parquet reader; the next run removes the leftover and the chunk
    is missing, so it runs again."""
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    _run_stored(Tiny(), 0, store.files)
    script = ("import os, signal, sys\n"
              "sys.path.insert(0, sys.argv[1])\n"
              "from test_sweep_store import Tiny\n"
              "from pipeplug_harness.sweep import engine, store\n"
              "store.os.replace = lambda a, b: os.kill(os.getpid(), signal.SIGKILL)\n"
              "files = store.ChunkFiles(store.Path(sys.argv[2]), int(sys.argv[3]), sys.argv[4])\n"
              "engine._run_stored(Tiny(), 1, files)\n")
    proc = subprocess.run([sys.executable, "-c", script, str(Path(__file__).parent),
                           str(store.folder), str(store.files.width), store.files.token],
                          check=False)
    assert proc.returncode == -9
    left = [p.name for p in store.folder.glob(".part-000001.parquet.*.tmp")]
    assert len(left) == 1
    assert not store.done(1) and [p.name for p in store.parts()] == ["part-000000.parquet"]
    assert pq.read_table(store.folder).equals(Tiny().run_chunk(0))
    store.close()
    again = ChunkStore(store.folder, Tiny.digest, Tiny.n_chunks)
    assert [c for c in range(3) if not again.done(c)] == [1, 2]
    assert not list(store.folder.glob(".*.tmp"))


def test_a_folder_of_someone_else_is_refused_and_left_as_it_was(tmp_path):
    """A folder without a manifest holding files named like chunks: they were deleted before."""
    folder = tmp_path / "theirs"
    folder.mkdir()
    (folder / "part-000000.parquet").write_bytes(b"their data")
    (folder / "notes.txt").write_text("mine")
    with pytest.raises(UserError, match="a new or empty folder, or one a pipeplug command wrote"):
        ChunkStore(folder, Tiny.digest, Tiny.n_chunks, fresh=True)
    assert (folder / "part-000000.parquet").read_bytes() == b"their data"
    assert sorted(p.name for p in folder.iterdir() if not p.name.startswith(".")) == [
        "notes.txt", "part-000000.parquet"]


def test_afresh_removes_only_the_files_the_manifest_names(tmp_path):
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    _run_stored(Tiny(), 0, store.files)
    store.close()
    (store.folder / "part-000099.parquet").write_bytes(b"not a chunk of this campaign")
    again = ChunkStore(store.folder, "another", 2, fresh=True)
    assert not again.done(0)
    assert (store.folder / "part-000099.parquet").read_bytes() == b"not a chunk of this campaign"
    again.close()


def test_a_second_campaign_into_a_folder_in_use_is_refused(tmp_path):
    """Two sweeps into one folder (the second with --fresh) both ran and mixed their rows."""
    first = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    with pytest.raises(UserError, match="no other pipeplug command is writing into"):
        ChunkStore(tmp_path / "out", "another", 5, fresh=True)
    first.close()
    ChunkStore(tmp_path / "out", "another", 5, fresh=True).close()


def test_a_writer_never_writes_into_a_folder_taken_over(tmp_path):
    """The manifest holds another run's token (the lock did not hold, e.g. on a file system
    without locks): neither a worker nor the client writes a chunk."""
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    store.close()
    other = OutputFolder(tmp_path / "out", "sweep", {"campaign": "another"})
    assert not store.files.visible()
    data = _run_stored(Tiny(), 1, store.files)               # bytes: the worker did not write
    assert isinstance(data, bytes) and not store.done(1)
    with pytest.raises(RunFailed, match="another command took over"):
        store.write(1, data)
    assert not store.done(1)
    other.release()


def test_a_refused_campaign_leaves_the_folder_as_it_was(tmp_path):
    """A second campaign refused (without --fresh) rewrote the manifest as its own first, so a
    rerun with --fresh removed only the chunks the refused one named: the first campaign's
    other chunks stayed in the dataset, mixed with the new rows."""
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    for c in range(Tiny.n_chunks):
        _run_stored(Tiny(), c, store.files)
    store.close()
    before = (store.folder / MANIFEST).read_text()
    with pytest.raises(UserError, match="holds another campaign"):
        ChunkStore(store.folder, "another", 1)
    assert (store.folder / MANIFEST).read_text() == before
    again = ChunkStore(store.folder, "another", 1, fresh=True)
    assert again.parts() == []
    again.close()


def test_another_command_into_a_campaigns_folder_is_refused(tmp_path):
    """A scene run into a finished campaign's folder was accepted and rewrote the manifest as
    the scene's, after which the sweep's Parquet dataset no longer read: it is refused, and the
    campaign's folder stays as it was."""
    store = ChunkStore(tmp_path / "out", Tiny.digest, Tiny.n_chunks)
    _run_stored(Tiny(), 0, store.files)
    store.close()
    before = {p.name: p.read_bytes() for p in store.folder.iterdir()}
    with pytest.raises(UserError, match="holds the output of pipeplug sweep"):
        OutputFolder(store.folder, "scene")
    assert {p.name: p.read_bytes() for p in store.folder.iterdir()} == before
    assert read_folder(store.folder).num_rows == 4


_BLOWS = {"pipe": {"L1": 1.0}, "plug": {"L2": 1.0, "tau2": 1e4},
          "soil": {"contact_growth": False}, "model": {"elastic": False},
          "blows": {"amplitude": 23e3}, "grid": {"tau1": ["10 kPa", "20 kPa"],
                                                   "duration": ["50 ms"]}}
_DRIVES = {"sweep": {"kind": "drive"}, "pipe": {"L1": 2.0}, "plug": {"L2": 2.0, "tau2": 2e4},
           "blows": {"amplitude": 23e3, "duration": 0.01, "period": 0.2},
           "model": {"elastic": False}, "drive": {"target": 0.02, "step": 0.01},
           "grid": {"tau1": [8e4]}}
#: units the files must carry (docs/files.md), written out here; the other columns have none
_BLOW_UNITS = {"tau1": "Pa", "duration": "s", "u_pipe": "m", "u_plug": "m", "v_pipe": "m/s",
               "v_plug": "m/s", "F_outer": "N", "F_inner": "N", "F_head": "N", "v_ram": "m/s",
               "stress_head": "Pa", "stress_min": "Pa", "stress_max": "Pa", "L2_now": "m",
               "t_end": "s", **{w: "J" for w in (
                   "W_input", "W_friction", "W_friction_outer", "W_friction_inner", "E_kinetic",
                   "E_strain", "W_numerical", "W_ram", "W_cushion", "E_transferred", "W_face",
                   "W_damping", "W_accretion", "W_removed")}}
_DRIVE_UNITS = {"tau1": "Pa", "penetration": "m", "last_set": "m", "drive_time": "s",
                "metres_per_hour": "m/h"}


@pytest.mark.parametrize("raw, runner, units, unitless", [
    (_BLOWS, "batch", _BLOW_UNITS, {"case", "at_rest", "pipe_mode", "plug_mode", "error"}),
    ({**_BLOWS, "output": {"modes": True}}, "case", _BLOW_UNITS,
     {"case", "at_rest", "pipe_mode", "plug_mode", "modes", "error"}),
    (_DRIVES, "case", _DRIVE_UNITS, {"case", "outcome", "refusal", "blows", "steps", "error"}),
])
def test_every_sweep_s_parquet_files_carry_their_units(tmp_path, raw, runner, units, unitless):
    """Each field's metadata holds its unit, in the file a worker writes and in the one the
    client writes from the bytes (they were None on every path)."""
    from pipeplug_harness.sweep.file import sweep_spec
    spec = sweep_spec("u", raw)
    assert spec.runner == runner
    for who, files in (("worker", True), ("client", False)):
        store = ChunkStore(tmp_path / who, spec.digest, spec.n_chunks)
        result = _run_stored(spec, 0, store.files if files else None)
        if not files:
            store.write(0, result)
        schema = pq.read_schema(store.path(0))
        got = {f.name: (f.metadata or {}).get(b"unit", b"").decode() for f in schema}
        assert {k: u for k, u in got.items() if u} == units
        assert {k for k, u in got.items() if not u} == unitless
        assert pq.read_table(store.path(0)).num_rows == spec.n_cases
        store.close()
