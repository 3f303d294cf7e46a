"""The progress of a long drive on stderr (tqdm): blows, penetration, rate and time left."""
from __future__ import annotations

import sys

__all__ = ["DriveProgress"]


class DriveProgress:
    """A progress bar over the target penetration [mm], updated after each blow (call it with
    the blow's record); tqdm estimates the time left from the recent sets. Shown when stderr
    is a terminal (or ``always``)."""

    def __init__(self, spec, always: bool = False, stream=sys.stderr):
        self._spec, self._always, self._stream = spec, always, stream
        self._bar = None
        self._depth = 0           # mm shown so far

    def __enter__(self) -> DriveProgress:
        from tqdm import tqdm
        self._bar = tqdm(total=round(self._spec.target * 1000), unit="mm", file=self._stream,
                         desc=self._spec.name, mininterval=1.0, leave=False,
                         disable=None if not self._always else False)
        return self

    def __call__(self, blow) -> None:
        depth = min(max(round(blow.penetration * 1000), 0), self._bar.total)
        self._bar.update(depth - self._depth)
        self._depth = depth
        self._bar.set_postfix_str(f"blow {blow.blow}, set {blow.set * 1000:.3g} mm",
                                  refresh=False)

    def __exit__(self, *exc) -> None:
        self._bar.close()
