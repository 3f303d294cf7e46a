"""A campaign's output folder: one Parquet file per finished chunk, and what campaign it holds.

The folder is an output folder of :mod:`pipeplug_harness.io.folder` (a manifest naming what it
holds, a lock while the campaign runs) and one Parquet dataset (``part-000000.parquet``, ...;
readers skip the ``_`` and ``.`` files). The manifest holds the campaign's digest, its chunk
count and the width of the chunk files' numbers, which name every chunk file the campaign may
write: only those are removed when a campaign starts afresh, never another file.

A chunk's file is written where the chunk ran when that process sees the folder
(:class:`ChunkFiles`: the task returns a :class:`Written` that the client does not fetch), else its
bytes travel to the client, which writes them. Either way the bytes are the same, written under
a temporary name of the writer's own and renamed into place, so a file is there whole or not at
all; a process stopped at any point leaves only finished chunks (and perhaps a ``.``-file,
removed when the folder is next opened), a chunk written twice is the same file, and a rerun
writes the missing ones. Before each write the writer reads this run's token in the manifest:
a folder another campaign has taken over is never written into.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

from pipeplug_harness import io
from pipeplug_harness.errors import RunFailed, UserError

__all__ = ["ChunkStore", "ChunkFiles", "Written", "read_folder", "PREFIX"]

PREFIX = "part-"


class Written(NamedTuple):
    """A worker's acknowledgement: it wrote chunk ``chunk`` (``rows`` rows) into the folder."""

    chunk: int
    rows: int


@dataclass(frozen=True)
class ChunkFiles:
    """Where and how chunk files are written: small, sent with every task.

    ``token`` is this run's, written in the folder's manifest by the client: a process sees
    the client's folder (the same file system, not a same-named folder of another machine), and
    the folder is still this run's, exactly when it reads that token there (:meth:`visible`)."""

    folder: Path
    width: int
    token: str

    def path(self, c: int) -> Path:
        return self.folder / chunk_name(c, self.width)

    def visible(self) -> bool:
        try:
            return json.loads((self.folder / io.MANIFEST).read_text()).get("run") == self.token
        except (OSError, ValueError):
            return False

    def write_bytes(self, c: int, data: bytes) -> None:
        """Write chunk ``c`` (a Parquet file's bytes) whole or not at all."""
        io.write_parquet(self.path(c), data=data)

    def write_table(self, c: int, table) -> Written:
        """Encode and write chunk ``c`` whole or not at all (the bytes of
        :func:`pipeplug_harness.io.parquet_bytes`)."""
        io.write_parquet(self.path(c), table)
        return Written(c, table.num_rows)


def chunk_name(c: int, width: int) -> str:
    return f"{PREFIX}{c:0{width}d}.parquet"


class ChunkStore:
    """The output folder of the campaign ``digest`` of ``n_chunks`` chunks (opened by the
    client: it locks the folder, checks and writes the manifest; :attr:`files` goes to the
    workers).

    Raises
    ------
    UserError
        The folder holds files of someone else, another campaign (without ``fresh``), or is
        held by a command running now.
    """

    def __init__(self, folder, digest: str, n_chunks: int, fresh: bool = False,
                 about: dict | None = None):
        width = max(6, len(str(n_chunks - 1)))

        def accept(held: dict) -> None:
            """Refuse another campaign's folder (without ``fresh``) before it is changed."""
            if held.get("campaign") not in (None, digest) and not fresh:
                raise UserError(f"{Path(folder).resolve()} holds another campaign (digest "
                                f"{held['campaign']}, this one {digest}): choose another "
                                f"output folder, or start afresh (--fresh)")

        self.out = io.OutputFolder(folder, "sweep", {"campaign": digest, "chunks": n_chunks,
                                                     "width": width, **(about or {})}, accept)
        self.folder = self.out.path
        held = self.out.previous
        if fresh or held.get("campaign") != digest:
            self._remove_chunks(held)
        for path in self.folder.glob(f".{PREFIX}*.tmp"):      # left by a process killed mid-write
            path.unlink(missing_ok=True)
        self.files = ChunkFiles(self.folder, width, self.out.token)

    def _remove_chunks(self, held: dict) -> None:
        """Remove the chunk files the earlier campaign of the manifest wrote (by its rule)."""
        chunks, width = held.get("chunks"), held.get("width")
        if isinstance(chunks, int) and isinstance(width, int):
            for c in range(chunks):
                (self.folder / chunk_name(c, width)).unlink(missing_ok=True)

    def path(self, c: int) -> Path:
        return self.files.path(c)

    def done(self, c: int) -> bool:
        return self.path(c).exists()

    def write(self, c: int, data: bytes) -> None:
        """Write chunk ``c`` from its Parquet bytes, whole or not at all, after checking the
        folder is still this campaign's."""
        if not self.files.visible():
            raise RunFailed(f"{self.folder}: another command took over this output folder; this "
                            f"campaign stops without writing there")
        self.files.write_bytes(c, data)

    def parts(self) -> list[Path]:
        return sorted(self.folder.glob(f"{PREFIX}*.parquet"))

    def close(self) -> None:
        self.out.release()


def read_folder(folder):
    """Every row of a campaign's output folder, in case order (the chunk files its manifest
    names)."""
    folder = Path(folder)
    try:
        held = json.loads((folder / io.MANIFEST).read_text())
        names = [chunk_name(c, held["width"]) for c in range(held["chunks"])]
    except (OSError, ValueError, KeyError, TypeError):
        raise UserError(f"no campaign's results ({io.MANIFEST} missing or unreadable)",
                        file=folder) from None
    parts = [folder / n for n in names if os.path.exists(folder / n)]
    if not parts:
        raise UserError("no results", file=folder)
    return io.read_parquet(parts)
