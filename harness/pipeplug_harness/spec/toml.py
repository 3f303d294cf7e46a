"""Reading a TOML file: the only place the harness parses TOML."""
from __future__ import annotations

import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:                                   # pragma: no cover - Python 3.10
    import tomli as tomllib

from pipeplug_harness.errors import UserError

__all__ = ["read_toml", "MAX_BYTES"]

#: the largest file read [bytes]: a scene, drive or sweep file is a few kB
MAX_BYTES = 16 * 2 ** 20


def read_toml(path) -> dict:
    """The parsed TOML file ``path``, unchecked.

    Raises
    ------
    UserError
        The file is missing, a folder, unreadable, not UTF-8 or not valid TOML (with the
        parser's line and column).
    """
    path = Path(path)
    try:
        if path.exists() and not path.is_dir() and not path.is_file():
            raise UserError("is not a regular file", file=path)
        if path.is_file() and path.stat().st_size > MAX_BYTES:
            raise UserError(f"is larger than {MAX_BYTES} bytes: not a scene, drive or sweep file",
                            file=path)
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise UserError("no such file", file=path) from None
    except IsADirectoryError:
        raise UserError("is a folder, not a file", file=path) from None
    except PermissionError:
        raise UserError("cannot be read (permission denied)", file=path) from None
    except UnicodeDecodeError as exc:
        raise UserError(f"not a text file (UTF-8): {exc.reason}", file=path) from None
    except tomllib.TOMLDecodeError as exc:
        raise UserError(f"not valid TOML: {exc}", file=path) from None
    except RecursionError:
        raise UserError("not valid TOML: nested too deeply", file=path) from None
    except OSError as exc:
        raise UserError(f"cannot be read: {exc.strerror or exc}", file=path) from None
