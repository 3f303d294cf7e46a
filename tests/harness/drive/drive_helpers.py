"""Shared helpers of the drive tests."""
from __future__ import annotations


def toml_text(sections: dict) -> str:
    """A drive file from nested dicts (numbers written exactly)."""
    lines = []
    for section, keys in sections.items():
        lines.append(f"[{section}]")
        for key, value in keys.items():
            if isinstance(value, bool):
                text = "true" if value else "false"
            elif isinstance(value, str):
                text = f'"{value}"'
            else:
                text = repr(int(value) if isinstance(value, int) else float(value))
            lines.append(f"{key} = {text}")
    return "\n".join(lines) + "\n"
