"""Output folders that never lose data.

A command writes only into a folder that is new, empty, or holds its manifest ``_pipeplug.json``
(a folder an earlier run of the same ``pipeplug`` command wrote): a non-empty folder without one
is refused, so a user's own files are never overwritten or removed, and so is a folder holding
another command's manifest, whose results would be replaced or mixed. A refused run leaves the
folder as it was (not even a lock file). The manifest names the files the commands
wrote there (and a campaign's chunk files by their rule); only those are ever replaced or
removed. While a command runs it holds a lock on the folder (``.pipeplug.lock``, an advisory
lock the system releases when the process ends, however it ends), so a second command into the
same folder is refused until the first is done; and before each write a writer checks that the
manifest still holds its own run's token, so a run whose folder was taken over stops instead of
mixing its files with another's.
"""
from __future__ import annotations

import json
import os
import uuid
from pathlib import Path

from pipeplug_harness.errors import RunFailed, UserError

__all__ = ["OutputFolder", "MANIFEST", "LOCK", "foreign"]

MANIFEST = "_pipeplug.json"
LOCK = ".pipeplug.lock"
_OWN = (MANIFEST, LOCK)


def _prepared(path: Path) -> Path:
    """``path`` as a folder this process can write into (created when missing)."""
    if path.exists() and not path.is_dir():
        raise UserError(key="--out", value=str(path), allowed="a folder (this is a file)")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserError(key="--out", value=str(path),
                        allowed=f"a folder that can be created ({exc.strerror or exc})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise UserError(key="--out", value=str(path),
                        allowed="a folder this user can write into (it is read-only)")
    return path


def _lock_file(path: Path):
    """The lock file at ``path``, opened (made when missing), and whether this call made it."""
    while True:
        try:
            return open(path, "x"), True
        except FileExistsError:
            pass
        try:
            return open(path, "r+"), False
        except FileNotFoundError:                # removed in between: make it
            continue


def _check_owner(folder: Path, given, held: dict | None, command: str) -> None:
    """Refuse a folder (``given``: as the user named it) that holds files without a manifest
    (someone else's), or the manifest of another command: its files are that command's results
    (a sweep's dataset, a scene's CSV and PNG), which this one would replace or mix with its
    own."""
    if held is None and any(p.name not in _OWN for p in folder.iterdir()):
        raise UserError(key="--out", value=str(given),
                        allowed=f"a new or empty folder, or one a pipeplug command wrote "
                                f"(with {MANIFEST}); this one holds other files")
    if held is not None and held.get("command") != command:
        raise UserError(key="--out", value=str(given),
                        allowed=f"a new or empty folder, or one pipeplug {command} wrote; this "
                                f"one holds the output of pipeplug {held.get('command')} "
                                f"({MANIFEST}): choose another folder")


def _inside(root: Path, name: str) -> bool:
    """Whether the file ``name`` of a manifest lies inside the folder ``root`` (resolved): not
    an absolute path, no ``..`` out of it, no folder on the way that links elsewhere."""
    if Path(name).is_absolute():
        return False
    parent = (root / name).parent.resolve()
    return (parent == root or root in parent.parents) and ".." not in Path(name).parts


def _remove_if_empty(root: Path, folder: Path) -> None:
    """Remove ``folder`` and its parents up to ``root`` (excluded) while they are empty: a
    folder holding anything, the user's or not, stays."""
    while folder != root and root in folder.parents:
        try:
            folder.rmdir()
        except OSError:
            return
        folder = folder.parent


def foreign(folder, name: str) -> bool:
    """Whether ``folder`` holds a file ``name`` that its manifest does not name (one a command
    must not write over), read without opening the folder: for a check before a run starts."""
    return os.path.lexists(Path(folder) / name) and not listed(folder, name)


def listed(folder, name: str) -> bool:
    """Whether the manifest of ``folder`` names a file ``name``: one a pipeplug command wrote
    there (read without opening the folder; an unreadable manifest names none)."""
    try:
        held = json.loads((Path(folder) / MANIFEST).read_text())
        return name in held.get("files", [])
    except (OSError, ValueError, AttributeError):
        return False


class OutputFolder:
    """The output folder of one command run (see the module docstring).

    Parameters
    ----------
    path : path
        The folder (created when missing).
    command : str
        What writes there (e.g. ``"scene"``), recorded in the manifest.
    about : dict, optional
        More to record in the manifest (e.g. a campaign's digest); what an earlier command
        recorded there and ``about`` does not replace is kept.
    accept : callable, optional
        ``accept(previous)`` with the folder's earlier manifest (``{}`` without one), called
        before the folder is changed: it raises :class:`UserError` to refuse the folder (e.g.
        another campaign's), which is then left as it was.

    Raises
    ------
    UserError
        The path is a file, cannot be created or written, holds files of someone else or the
        output of another command, or another command holds the folder.
    """

    def __init__(self, path, command: str, about: dict | None = None, accept=None):
        self.path = _prepared(Path(path)).resolve()
        self.token = uuid.uuid4().hex
        self._lock, created = self._locked()
        try:
            held = self.manifest()
            _check_owner(self.path, path, held, command)
            if accept is not None:
                accept(held or {})
        except BaseException:
            # A refused run leaves the folder as it was: the lock file goes if this run made
            # it (removed while still locked, so no other run holds that file now).
            if created:
                (self.path / LOCK).unlink(missing_ok=True)
            self.release()
            raise
        self.previous = held or {}
        self.data = {**self.previous, "written_by": "pipeplug", "command": command,
                     "run": self.token, "files": list(self.previous.get("files", [])),
                     **(about or {})}
        self._save()

    # Ownership ---------------------------------------------------------------------------------
    def _locked(self):
        """An advisory lock on the folder, held until :meth:`release` or the process ends;
        and whether this run made the lock file."""
        try:
            import fcntl
        except ImportError:                      # pragma: no cover - not POSIX: no lock
            fcntl = None
        while True:
            fh, created = _lock_file(self.path / LOCK)
            if fcntl is None:                    # pragma: no cover
                return fh, created
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                fh.close()
                raise UserError(key="--out", value=str(self.path),
                                allowed="a folder no other pipeplug command is writing into (one "
                                        "is running there now: wait for it, or choose another "
                                        "folder)") from None
            # A refused run removes the lock file it made: one opened before that removal and
            # locked after it is no longer the folder's, so lock the folder's file again.
            try:
                same = os.stat(self.path / LOCK).st_ino == os.fstat(fh.fileno()).st_ino
            except FileNotFoundError:
                same = False
            if same:
                return fh, created
            fh.close()

    def release(self) -> None:
        """Release the folder's lock."""
        if self._lock is not None:
            self._lock.close()
            self._lock = None

    def manifest(self) -> dict | None:
        """The folder's manifest (None without one)."""
        try:
            data = json.loads((self.path / MANIFEST).read_text())
        except FileNotFoundError:
            return None
        except (OSError, ValueError) as exc:
            raise UserError(f"{MANIFEST} cannot be read ({exc}): not a folder a pipeplug command "
                            f"wrote", file=self.path) from None
        if not isinstance(data, dict) or data.get("written_by") != "pipeplug":
            raise UserError(f"{MANIFEST} was not written by pipeplug", file=self.path)
        return data

    def still_mine(self) -> None:
        """Raise :class:`RunFailed` unless the manifest still holds this run's token."""
        try:
            held = json.loads((self.path / MANIFEST).read_text()).get("run")
        except (OSError, ValueError):
            held = None
        if held != self.token:
            raise RunFailed(f"{self.path}: another command took over this output folder; this "
                            f"run stops without writing there")

    def _save(self) -> None:
        tmp = self.path / f".{MANIFEST}.{self.token}.tmp"
        tmp.write_text(json.dumps(self.data, indent=1, default=str))
        os.replace(tmp, self.path / MANIFEST)

    # Files -------------------------------------------------------------------------------------
    def file(self, name: str) -> Path:
        """The path to write the file ``name`` at, recorded in the manifest first (after
        checking the folder is still this run's, and that a file of that name there is one a
        pipeplug command wrote: another is never written over)."""
        self.still_mine()
        if name not in self.data["files"]:
            if os.path.lexists(self.path / name):
                raise UserError(key="--out", value=str(self.path),
                                allowed=f"a folder whose files pipeplug may write: {name} is "
                                        f"there and is not one {MANIFEST} names (move it, or "
                                        f"choose another folder)")
            self.data["files"].append(name)
            self._save()
        return self.path / name

    def owned(self) -> list[Path]:
        """The files the manifest names that exist."""
        return [self.path / n for n in self.data["files"] if (self.path / n).exists()]

    def remove_owned(self, names=None) -> None:
        """Remove the files of the manifest (or those of ``names`` it holds), and the folders
        inside this one that they leave empty (``failures/``); never others."""
        self.still_mine()
        keep = []
        for name in self.data["files"]:
            if names is None or name in names:
                if _inside(self.path, name):   # a manifest edited to "../x" deletes nothing
                    (self.path / name).unlink(missing_ok=True)
                    _remove_if_empty(self.path, (self.path / name).parent)
            else:
                keep.append(name)
        self.data["files"] = keep
        self._save()

    def update(self, **about) -> None:
        """Record more in the manifest."""
        self.still_mine()
        self.data.update(about)
        self._save()

    def __enter__(self) -> OutputFolder:
        return self

    def __exit__(self, *exc) -> None:
        self.release()
