"""Shared helpers of the fuzz tests."""
from __future__ import annotations

import re


def count(pattern: str, text: str) -> int:
    """The integer that ``pattern``'s first group finds in a fuzz summary ``text`` (the test
    fails, showing the text, when it is not there)."""
    match = re.search(pattern, text)
    assert match, text
    return int(match.group(1))
