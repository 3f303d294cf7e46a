"""Aggregating case results: the summary table, failing-case files and replays.

Aggregation is separate from running: :class:`Summary` takes results in any order (from one
process, a pool or a cluster) and gives the same table.
"""
from __future__ import annotations

import json
import math
import shlex
from collections import Counter
from pathlib import Path

from pipeplug_harness.errors import UserError

from .cases import Case, case_from_json, case_to_json
from .checks import CHECKS
from .elastic_cases import elastic_from_json, elastic_to_json
from .growth_cases import growth_from_json, growth_to_json
from .ram_cases import ram_from_json, ram_to_json
from .run import CaseResult

__all__ = ["Summary", "save_failure", "load_failure"]


class Summary:
    """Counts, failures and worst values per ``(check, subject)`` over many cases."""

    def __init__(self):
        self.cases = 0
        self.models = Counter()
        self.families = Counter()
        self.fd = Counter()
        self.fd_results: list[tuple] = []
        self.rows: dict[tuple[str, str], list] = {}   # key -> [cases, failed, worst, where]
        self.failed_cases: list[tuple[int, int]] = []
        self.case_seconds = 0.0

    def add(self, result: CaseResult) -> None:
        self.cases += 1
        self.models[result.model] += 1
        self.families.update(result.families)
        self.case_seconds += result.seconds
        if result.fd is not None:
            self.fd_results.append(result.fd)
            resolved, grazing, _, order, _, _, levels = result.fd
            self.fd.update(resolved=resolved, grazing=resolved and grazing,
                           order=order == order, refined=levels > 3)
        failed = set(result.failed)
        for key, value in result.values.items():
            row = self.rows.setdefault(key, [0, 0, 0.0, None])
            row[0] += 1
            row[1] += key in failed
            if row[2] == row[2] and not value <= row[2]:          # NaN is the worst
                row[2], row[3] = value, (result.seed, result.index)
        if failed:
            self.failed_cases.append((result.seed, result.index))

    @property
    def failures(self) -> int:
        """Number of failing cases."""
        return len(self.failed_cases)

    def count(self, check: str, subject: str | None = None) -> int:
        """Cases on which ``check`` ran (on ``subject``, or the most on any subject)."""
        counts = [row[0] for (c, s), row in self.rows.items()
                  if c == check and (subject is None or s == subject)]
        return max(counts, default=0)

    def table(self, seconds: float | None = None, workers: int = 1) -> str:
        """The summary as text: totals, then one line per check and subject."""
        fam = self.families
        models = ", ".join(f"model {m} {n}" for m, n in sorted(self.models.items()))
        lines = [
            f"cases: {self.cases} ({models}); "
            f"against the reference: {fam['reference']}; through the FMU: {fam['fmu']}; "
            f"fd: {fam['fd']} (resolved {self.fd['resolved']}, grazing {self.fd['grazing']}, "
            f"order measured {self.fd['order']}, refined {self.fd['refined']})",
            f"failing cases: {self.failures}",
        ]
        if seconds is not None:
            lines.append(f"time: {seconds:.1f} s wall, {self.case_seconds:.1f} s in cases, "
                         f"{workers} worker(s)")
        width = max((len(c) + len(s) for c, s in self.rows), default=10) + 3
        lines += ["", f"{'check [subject]':<{width}} {'cases':>7} {'failed':>6} "
                      f"{'worst':>9} {'tolerance':>9}  worst case (seed:index)",
                  "-" * (width + 60)]
        for check in CHECKS:
            for (c, subject), (n, failed, worst, where) in sorted(self.rows.items()):
                if c != check:
                    continue
                tag = f"{check} [{subject}]"
                case = f"{where[0]}:{where[1]}" if where and worst > 0 else "-"
                lines.append(f"{tag:<{width}} {n:>7} {failed:>6} {_num(worst):>9} "
                             f"{_num(CHECKS[check].tolerance):>9}  {case}")
        return "\n".join(lines)


def _num(x: float) -> str:
    if x == 0:
        return "0"
    if math.isinf(x) or math.isnan(x):
        return str(x)
    return f"{x:.2e}" if abs(x) < 1e-2 or abs(x) >= 1e3 else f"{x:.3f}"


def save_failure(result: CaseResult, case: Case, folder, paths: tuple) -> Path:
    """Write a failing case as a replayable JSON file; return its path. ``folder`` is a
    folder, or an output folder (:class:`pipeplug_harness.io.OutputFolder`) whose manifest then
    names the file."""
    name = f"case-{case.seed}-{case.index}.json"
    if hasattr(folder, "file"):
        (folder.path / "failures").mkdir(exist_ok=True)
        path = folder.file(f"failures/{name}")
    else:
        folder.mkdir(parents=True, exist_ok=True)
        path = folder / name
    data = {
        "seed": case.seed, "index": case.index, "paths": list(paths),
        "failed": [{"check": c, "subject": s, "value": result.values[(c, s)],
                    "tolerance": CHECKS[c].tolerance} for c, s in result.failed],
        "errors": [{"check": c, "subject": s, "message": m}
                   for (c, s), m in result.errors.items()],
        # the file's whole path: the command works from any folder (its name alone did only
        # from the failures folder)
        "replay": f"pipeplug fuzz --replay {shlex.quote(str(Path(path).resolve()))}",
        "case": _TO_JSON[getattr(case, "kind", "rigid")](case),
    }
    path.write_text(json.dumps(data, indent=1, default=_plain))
    return path


def _plain(value):
    return float(value) if hasattr(value, "__float__") else str(value)


def load_failure(path: str | Path) -> tuple[Case, dict]:
    """The case of a file written by :func:`save_failure` (or a bare case file), and the
    file's data."""
    path = Path(path)
    if not path.exists():
        raise UserError("no such fuzz case file", file=path)
    if not path.is_file() or path.stat().st_size > 2 ** 26:
        raise UserError("not a fuzz case file (a regular file of at most 64 MB)", file=path)
    try:
        data = json.loads(path.read_text())
        case = data.get("case", data)
        return _FROM_JSON[case.get("kind", "rigid")](case), data
    except (OSError, ValueError, TypeError, KeyError, AttributeError, RecursionError) as exc:
        raise UserError(f"not a fuzz case file: {type(exc).__name__}: {exc}", file=path) \
            from None


#: case kind -> its JSON writer and reader
_TO_JSON = {"rigid": case_to_json, "elastic": elastic_to_json, "ram": ram_to_json,
            "growth": growth_to_json}
_FROM_JSON = {"rigid": case_from_json, "elastic": elastic_from_json, "ram": ram_from_json,
              "growth": growth_from_json}
