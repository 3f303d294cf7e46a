"""Shared helpers of the drive tests."""
from __future__ import annotations

#: What a drive file must give, with the values the tests' drives had when these were the
#: files' defaults (the paper's pipe and plug, no soil friction, its blow every 0.1 s).
REQUIRED = {"pipe": {"L1": 1.0}, "plug": {"L2": 1.0, "tau2": 1.0e4}, "soil": {"tau1": 0.0},
            "blows": {"amplitude": 23000.0, "duration": 0.05, "period": 0.1}}


def complete(sections: dict) -> dict:
    """``sections`` with every required section and key filled in from :data:`REQUIRED`."""
    out = {name: dict(keys) for name, keys in REQUIRED.items()
           if not (name == "blows" and "hammer" in sections)}
    for name, keys in sections.items():
        out.setdefault(name, {}).update(keys)
    if "rate" in out.get("blows", {}):
        out["blows"].pop("period")
    return out


def toml_text(sections: dict, fill: bool = True) -> str:
    """A drive file from nested dicts (numbers written exactly); the required sections filled
    in unless ``fill`` is false."""
    lines = []
    for section, keys in (complete(sections) if fill else sections).items():
        lines.append(f"[{section}]")
        for key, value in keys.items():
            lines.append(f"{key} = {_value(value)}")
    return "\n".join(lines) + "\n"


def _value(value) -> str:
    """``value`` as TOML (numbers exactly; lists item by item)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    return repr(int(value) if isinstance(value, int) else float(value))
