"""The two ways a ``pipeplug`` command ends badly, and their exit codes.

* :class:`UserError` (exit code 2): the user asked for something the command refuses (a file
  that is missing or unreadable, an unknown key, a value outside its allowed range, an output
  folder that is not the command's, work past a stated limit). The command prints one line on
  stderr naming the file, the key, the value and what is allowed, and never a traceback.
* :class:`RunFailed` (exit code 1): the run itself failed (a check of the results did not
  hold, the FMU refused a step): one line too.

Every check that refuses user input raises :class:`UserError`; :func:`pipeplug_harness.cli.main`
turns both into their line and exit code.
"""
from __future__ import annotations

__all__ = ["UserError", "RunFailed", "USER_ERROR", "RUN_FAILED"]

USER_ERROR, RUN_FAILED = 2, 1


class UserError(ValueError):
    """A user mistake: what was refused, where, and what is allowed.

    Parameters
    ----------
    message : str
        What is wrong, in one line (it may already name the key and value).
    file : str, optional
        The file the mistake is in (put before the message).
    key : str, optional
        ``[section] key`` or a command-line flag; with ``value`` and ``allowed`` the message
        is built from them when ``message`` is empty.
    value : object, optional
    allowed : str, optional
        The allowed range or set, in words.
    """

    def __init__(self, message: str = "", *, file=None, key: str | None = None,
                 value: object = None, allowed: str | None = None):
        if not message:
            message = f"{key} = {value!r}; allowed: {allowed}"
        self.file, self.key, self.value, self.allowed = file, key, value, allowed
        self.message = message
        super().__init__(f"{file}: {message}" if file is not None else message)

    def in_file(self, file) -> UserError:
        """The same mistake, naming ``file`` (when it names none yet)."""
        if self.file is not None:
            return self
        return UserError(self.message, file=file, key=self.key, value=self.value,
                         allowed=self.allowed)


class RunFailed(RuntimeError):
    """A run that cannot give a result (one line saying why)."""
