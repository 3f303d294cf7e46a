"""A campaign's output folder: one Parquet file per finished chunk, and what campaign it holds.

The folder is one Parquet dataset (``part-000000.parquet``, ...; readers skip the ``_`` and
``.`` files). A chunk's file is written where the chunk ran when that process sees the folder
(:class:`ChunkFiles`: the task returns a :class:`Written` that the client does not fetch), else its
bytes travel to the client, which writes them (:func:`parquet_bytes`). Either way the bytes are
the same, written under a temporary name of the writer's own and renamed into place, so a file
is there whole or not at all: a process stopped at any point leaves only finished chunks (and
perhaps a ``.``-file, removed when the folder is next opened), a chunk written twice is the
same file, and a rerun writes the missing ones. ``_campaign.json`` holds the campaign's digest
and a token of this run; a folder holding another campaign is refused (or emptied with
``fresh``).
"""
from __future__ import annotations

import json
import os
import uuid
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import pyarrow as pa
import pyarrow.parquet as pq

__all__ = ["ChunkStore", "ChunkFiles", "Written", "StoreError", "read_folder", "parquet_bytes"]

_MANIFEST = "_campaign.json"
_PREFIX = "part-"


class StoreError(ValueError):
    """The output folder holds another campaign."""


class Written(NamedTuple):
    """A worker's acknowledgement: it wrote chunk ``chunk`` (``rows`` rows) into the folder."""

    chunk: int
    rows: int


@dataclass(frozen=True)
class ChunkFiles:
    """Where and how chunk files are written: small, sent with every task.

    ``token`` is this run's, written in the folder's manifest by the client: a process sees
    the client's folder (the same file system, not a same-named folder of another machine)
    exactly when it reads that token there (:meth:`visible`)."""

    folder: Path
    width: int
    token: str

    def path(self, c: int) -> Path:
        return self.folder / f"{_PREFIX}{c:0{self.width}d}.parquet"

    def visible(self) -> bool:
        try:
            return json.loads((self.folder / _MANIFEST).read_text()).get("run") == self.token
        except (OSError, ValueError):
            return False

    def write_bytes(self, c: int, data: bytes) -> None:
        """Write chunk ``c`` (a Parquet file's bytes, :func:`parquet_bytes`) whole or not at
        all."""
        self._replace(c, lambda tmp: tmp.write_bytes(data))

    def write_table(self, c: int, table: pa.Table) -> Written:
        """Encode and write chunk ``c`` whole or not at all (the bytes of
        :func:`parquet_bytes`)."""
        self._replace(c, lambda tmp: _encode(table, str(tmp)))
        return Written(c, table.num_rows)

    def _replace(self, c: int, write) -> None:
        # A temporary name of this writer's own: two processes running the same chunk (one of
        # them thought dead) never write into one file; the rename is atomic and both bring
        # the same bytes.
        final = self.path(c)
        tmp = final.with_name(f".{final.name}.{uuid.uuid4().hex}.tmp")
        try:
            write(tmp)
            os.replace(tmp, final)
        finally:
            tmp.unlink(missing_ok=True)


class ChunkStore:
    """The output folder of the campaign ``digest`` of ``n_chunks`` chunks (opened by the
    client: it checks and writes the manifest; :attr:`files` goes to the workers)."""

    def __init__(self, folder: str | os.PathLike, digest: str, n_chunks: int,
                 fresh: bool = False, about: dict | None = None):
        self.folder = Path(folder).resolve()
        self.folder.mkdir(parents=True, exist_ok=True)
        self.files = ChunkFiles(self.folder, max(6, len(str(n_chunks - 1))), uuid.uuid4().hex)
        manifest = self.folder / _MANIFEST
        if manifest.exists():
            held = json.loads(manifest.read_text()).get("digest")
            if held != digest and not fresh:
                raise StoreError(f"{self.folder} holds another campaign (digest {held}, this one "
                                 f"{digest}): choose another output folder, or start afresh")
        if fresh or not manifest.exists() or held != digest:
            for path in self.parts():
                path.unlink()
        for path in self.folder.glob(f".{_PREFIX}*.tmp"):      # left by a process killed mid-write
            path.unlink(missing_ok=True)
        text = json.dumps({"digest": digest, "chunks": n_chunks, "run": self.files.token,
                           **(about or {})}, indent=1, default=str)
        tmp = manifest.with_name(f".{_MANIFEST}.tmp")
        tmp.write_text(text)
        os.replace(tmp, manifest)

    def path(self, c: int) -> Path:
        return self.files.path(c)

    def done(self, c: int) -> bool:
        return self.path(c).exists()

    def write(self, c: int, data: bytes) -> None:
        """Write chunk ``c`` from its Parquet bytes, whole or not at all."""
        self.files.write_bytes(c, data)

    def parts(self) -> list[Path]:
        return sorted(self.folder.glob(f"{_PREFIX}*.parquet"))


def _encode(table: pa.Table, where) -> None:
    """Only the text columns are dictionary-encoded: tried on computed floats, a dictionary
    only grows until it is dropped (it made encoding 2.5 times slower and the file larger)."""
    text = [f.name for f in table.schema if pa.types.is_string(f.type)]
    pq.write_table(table, where, use_dictionary=text)


def parquet_bytes(table: pa.Table) -> bytes:
    """The Parquet file of ``table``, in memory (the bytes :meth:`ChunkFiles.write_table`
    writes)."""
    sink = pa.BufferOutputStream()
    _encode(table, sink)
    return sink.getvalue().to_pybytes()


def read_folder(folder: str | os.PathLike) -> pa.Table:
    """Every row of a campaign's output folder, in case order (all part files, as written)."""
    parts = sorted(Path(folder).glob(f"{_PREFIX}*.parquet"))
    if not parts:
        raise FileNotFoundError(f"no results in {folder}")
    return pa.concat_tables([pq.read_table(p) for p in parts])
