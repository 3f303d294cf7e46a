"""A campaign's output folder: one Parquet file per finished chunk, and what campaign it holds.

The folder is one Parquet dataset (``part-000000.parquet``, ...; readers skip the ``_`` and
``.`` files). A chunk's file is encoded where the chunk ran (:func:`parquet_bytes`: the encoding
costs about as much as a compiled single blow, so the workers share it instead of the one
process collecting), then written under a temporary name and renamed into place, so a file
is there whole or not at all: a run stopped at any point leaves only finished chunks, and a
rerun writes the missing ones. ``_campaign.json`` holds the campaign's digest; a folder holding
another campaign is refused (or emptied with ``fresh``).
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

__all__ = ["ChunkStore", "StoreError", "read_folder", "parquet_bytes"]

_MANIFEST = "_campaign.json"
_PREFIX = "part-"


class StoreError(ValueError):
    """The output folder holds another campaign."""


class ChunkStore:
    """The output folder of the campaign ``digest`` of ``n_chunks`` chunks."""

    def __init__(self, folder: str | os.PathLike, digest: str, n_chunks: int,
                 fresh: bool = False, about: dict | None = None):
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self._width = max(6, len(str(n_chunks - 1)))
        manifest = self.folder / _MANIFEST
        if manifest.exists():
            held = json.loads(manifest.read_text()).get("digest")
            if held != digest and not fresh:
                raise StoreError(f"{self.folder} holds another campaign (digest {held}, this one "
                                 f"{digest}): choose another output folder, or start afresh")
        if fresh or not manifest.exists() or held != digest:
            for path in self.parts():
                path.unlink()
        manifest.write_text(json.dumps({"digest": digest, "chunks": n_chunks, **(about or {})},
                                       indent=1, default=str))

    def path(self, c: int) -> Path:
        return self.folder / f"{_PREFIX}{c:0{self._width}d}.parquet"

    def done(self, c: int) -> bool:
        return self.path(c).exists()

    def write(self, c: int, data: bytes) -> None:
        """Write chunk ``c`` (a Parquet file's bytes, :func:`parquet_bytes`) whole or not at
        all."""
        final = self.path(c)
        tmp = final.with_name(f".{final.name}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, final)

    def parts(self) -> list[Path]:
        return sorted(self.folder.glob(f"{_PREFIX}*.parquet"))


def parquet_bytes(table: pa.Table) -> bytes:
    """The Parquet file of ``table``, in memory. Only the text columns are dictionary-encoded:
    tried on computed floats, a dictionary only grows until it is dropped (it made encoding 2.5
    times slower and the file larger)."""
    text = [f.name for f in table.schema if pa.types.is_string(f.type)]
    sink = pa.BufferOutputStream()
    pq.write_table(table, sink, use_dictionary=text)
    return sink.getvalue().to_pybytes()


def read_folder(folder: str | os.PathLike) -> pa.Table:
    """Every row of a campaign's output folder, in case order (all part files, as written)."""
    parts = sorted(Path(folder).glob(f"{_PREFIX}*.parquet"))
    if not parts:
        raise FileNotFoundError(f"no results in {folder}")
    return pa.concat_tables([pq.read_table(p) for p in parts])
