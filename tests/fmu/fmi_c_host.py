"""The tests' plain C FMI host (``fmi_host.c``): compiled with the ``ziglang`` package's C
compiler, run as a subprocess with no Python in it, driven through its stdin.

:class:`CHost` sends one command a line and returns the answer and the log lines that came with
it; a crash of the host shows as :class:`HostDied` with its exit code and stderr.
:class:`CWorker` speaks the commands of the stateful test's FMPy worker
(``fmi_sequence_worker.py``) on top of it, so the same hypothesis rules drive either host.
"""
from __future__ import annotations

import os
import subprocess
import sys
import threading
from collections import deque
from pathlib import Path
from queue import Empty, Queue

HERE = Path(__file__).resolve().parent
LOG_CATEGORIES = {"logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                  "logAll"}


class HostDied(AssertionError):
    """The C host ended while a command was pending."""


def host_env(**variables) -> dict:
    """This process's environment without any PYTHON* variable, plus ``variables``."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env.update(variables)
    return env


def compile_host(dest: Path, source: str = "fmi_host.c", library: bool = False) -> Path:
    """Compile ``source`` (``fmi_host.c``, FMI 2.0, or ``fmi3_host.c``) into the executable
    ``dest`` (plain C: no libpython), or with ``library`` into the shared library ``dest`` that
    ``python_host3.py`` runs."""
    extra = ["-shared", "-fPIC", "-DPYTHON_HOST"] if library else []
    subprocess.run([sys.executable, "-m", "ziglang", "cc", "-O2", "-Wall", *extra, "-o",
                    str(dest), str(HERE / source)], check=True, capture_output=True)
    return dest


def hexed(text: str | bytes) -> str:
    """``text`` as the host's hex words ("-" for empty)."""
    data = text.encode() if isinstance(text, str) else text
    return data.hex() or "-"


def unhexed(word: str) -> str:
    return "" if word == "-" else bytes.fromhex(word).decode("utf-8", "replace")


def resource_uri(fmu_dir: Path) -> str:
    """The usual spelling: file:///abs/path/resources (as ``Path.as_uri`` writes it)."""
    return (Path(fmu_dir) / "resources").as_uri()


def guid_of(fmu_dir: Path) -> str:
    import xml.etree.ElementTree as ET

    return ET.parse(Path(fmu_dir) / "modelDescription.xml").getroot().get("guid")


class CHost:
    """One C host process with the FMU binary ``binary`` loaded (or another host speaking its
    commands, such as ``fmpy_host.py``).

    Parameters
    ----------
    exe : Path or list
        The compiled host, or the command line of another host.
    binary : Path
        ``binaries/linux64/PipePlug.so`` of an extracted FMU.
    env : dict, optional
        The host's environment.
    """

    def __init__(self, exe: Path, binary: Path, env: dict | None = None):
        argv = [str(exe)] if isinstance(exe, (str, Path)) else [str(w) for w in exe]
        self.proc = subprocess.Popen([*argv, str(binary)], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                     env=env)
        self._lines: Queue = Queue()
        self._stderr: deque = deque(maxlen=64)
        threading.Thread(target=self._read, daemon=True).start()
        # stderr read as it comes: a host that many commands go through (shared by tests)
        # must never block on a full pipe
        self._stderr_reader = threading.Thread(target=self._read_stderr, daemon=True)
        self._stderr_reader.start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            self._lines.put(line)
        self._lines.put(None)

    def _read_stderr(self) -> None:
        for line in self.proc.stderr:
            self._stderr.append(line)

    @property
    def stderr_tail(self) -> str:
        """The last 3000 characters the host wrote to stderr (all of it, once it ended)."""
        self._stderr_reader.join(timeout=10 if self.proc.poll() is not None else 0)
        return "".join(self._stderr)[-3000:]

    def alive(self) -> bool:
        return self.proc.poll() is None

    def __call__(self, *words) -> dict:
        """Send one command; its answer: ``status``, ``kind``, ``words`` and ``log``.

        ``log`` holds ``[instance, status, message, category]`` per line (category None when
        the FMU gave NULL).
        """
        log = []
        try:
            self.proc.stdin.write(" ".join(map(str, words)) + "\n")
            self.proc.stdin.flush()
            while True:
                line = self._lines.get(timeout=300)
                if line is None:
                    raise BrokenPipeError
                fields = line.split()
                if fields[:1] == ["@L"]:
                    category = None if fields[3] == "NULL" else unhexed(fields[3])
                    log.append([unhexed(fields[1]), int(fields[2]), unhexed(fields[4]), category])
                elif fields[:1] == ["@@"]:
                    return {"status": int(fields[1]), "kind": fields[2], "words": fields[3:],
                            "log": log}
        except (BrokenPipeError, Empty) as exc:
            try:
                code = self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                code = "none (hung)"
            raise HostDied(f"the C host died during {words[:3]}: exit code {code}\n"
                           f"{self.stderr_tail if code != 'none (hung)' else ''}"
                           ) from exc

    def close(self) -> int:
        """Quit; the host's exit code."""
        if self.alive():
            self.proc.stdin.write("quit\n")
            self.proc.stdin.flush()
        code = self.proc.wait(timeout=60)
        self.proc.stdout.close()
        return code

    def kill(self) -> None:
        """End the host at once."""
        self.proc.kill()
        self.proc.wait(timeout=60)
        self.proc.stdout.close()


def value_of(answer: dict):
    """The value of an answer, as FMPy's FMU2Slave gives it (None after a status > warning)."""
    kind, words = answer["kind"], answer["words"]
    if answer["status"] > 1 or kind in ("none", "null"):
        return None
    if kind == "int":
        return int(words[0])
    if kind == "hex":
        return "" if words[0] == "-" else words[0]
    convert = {"reals": float, "ints": int, "bools": lambda w: bool(int(w)), "strs": unhexed}[kind]
    return [convert(w) for w in words[1:]]


def _arg(value) -> str:
    """A number or None as a host word (repr round-trips doubles through strtod)."""
    return "none" if value is None else repr(float(value)) if isinstance(value, float) else str(
        value)


class CWorker:
    """The stateful test's worker commands (see ``fmi_sequence_worker.py``) on a C host."""

    def __init__(self, exe: Path, fmu_dir: Path, env: dict | None = None):
        self.host = CHost(exe, Path(fmu_dir) / "binaries" / "linux64" / "PipePlug.so", env)
        self.guid, self.uri = guid_of(fmu_dir), resource_uri(fmu_dir)

    def alive(self) -> bool:
        return self.host.alive()

    def __call__(self, op: str, **args) -> dict:
        if op == "instantiate":
            answer = self.host("instantiate", hexed(args["name"]), hexed(self.guid),
                               hexed(self.uri), 1)
            assert answer["kind"] == "int", answer
        elif op == "call":
            answer = self.host("call", args["id"], args["method"],
                               *_call_words(args["method"], args["args"]))
        elif op == "deserialize":
            answer = self.host("deserialize", args["id"], args["hex"] or "-")
        elif op in ("get_state", "free"):
            answer = self.host(op, args["id"])
        else:                                      # set_state, free_state, serialize
            answer = self.host(op, args["id"], args["state"])
        return {"status": answer["status"], "value": value_of(answer), "log": answer["log"]}

    def close(self) -> None:
        assert self.host.close() == 0


def _call_words(method: str, args: list) -> list:
    if method.startswith(("get", "set")) and method != "setupExperiment":
        vrs, values = args[0], (args[1] if len(args) > 1 else [])
        encode = hexed if method.endswith("String") else (
            lambda v: str(int(v))) if method.endswith(("Integer", "Boolean")) else _arg
        return [len(vrs), *vrs, *map(encode, values)]
    return [_arg(a) for a in args]
