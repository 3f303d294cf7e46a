"""The ``[model]`` choice ``elastic = "auto"``: the paper's criterion (section 4).

The rigid model is used when the blow lasts at least :data:`AUTO_RATIO` wave round trips
2 L1 / c1 of the pipe, the elastic model otherwise; the run says which and why.
"""
from __future__ import annotations

import math

from pipeplug_harness.errors import UserError

__all__ = ["AUTO_RATIO", "elastic_choice", "unused_model_keys"]

#: Blow duration / wave round trip at and above which "auto" picks the rigid model. The paper's
#: Fig. 7 case (ratio 125) differs from the elastic model by well under 1 % in peak velocity.
AUTO_RATIO = 20.0

_WAVE = {"L1": "[pipe] L1", "rho1": "[pipe] rho1", "E1": "[pipe] E1"}


def elastic_choice(choice, values: dict, duration: float) -> tuple[bool, str]:
    """Resolve ``elastic = "auto"`` by the paper's criterion and say why.

    Parameters
    ----------
    choice : bool or "auto"
    values : dict
        The file's start values (``None``: the FMU's default).
    duration : float
        The blow's duration [s].

    Raises
    ------
    UserError
        When "auto" needs L1, rho1 or E1 and one is not > 0 (the wave speed is undefined).
    """
    if isinstance(choice, bool):
        return choice, f"elastic = {str(choice).lower()} (given)"
    from pipeplug.params import Params
    given = {k: values[k] for k in _WAVE if values.get(k) is not None}
    p = Params().with_(**given)
    for name, where in _WAVE.items():
        if not getattr(p, name) > 0.0:
            raise UserError(key=where, value=getattr(p, name),
                            allowed='> 0 (elastic = "auto" needs the wave speed)')
    round_trip = 2.0 * p.L1 / math.sqrt(p.E1 / p.rho1)
    if duration == 0.0:                   # a ram striking the head directly: no cushion
        return True, (f"auto: a direct strike (no cushion) loads the head at once, within any "
                      f"wave round trip 2 L1/c1 = {round_trip:.3g} s -> elastic model")
    ratio = duration / round_trip
    rigid = ratio >= AUTO_RATIO
    verdict = "rigid" if rigid else "elastic"
    return (not rigid, f"auto: blow {duration:g} s = {ratio:.3g} x the wave round trip "
                       f"2 L1/c1 = {round_trip:.3g} s ({'>=' if rigid else '<'} {AUTO_RATIO:g}) "
                       f"-> {verdict} model")


#: the [model] keys only one model reads: the elastic grid's, and the rigid schemes'
_ELASTIC_ONLY = ("dx", "courant", "x_monitor")
_RIGID_ONLY = ("solver", "dt")


def unused_model_keys(choice, values: dict, elastic: bool) -> str:
    """The [model] keys of ``values`` (``None``: not given) that the chosen model does not read.

    A file that chose the model itself (``choice`` a bool) and gives a key of the other one
    made a slip (dt of the fd scheme on an elastic run, dx on a rigid one): refused. Under
    ``"auto"`` a file may give both models' keys for whichever is chosen: the text that says so
    (empty when none is unused).

    Raises
    ------
    UserError
        Naming the key, its value and the keys the chosen model reads.
    """
    unused = [k for k in (_RIGID_ONLY if elastic else _ELASTIC_ONLY) if values.get(k) is not None]
    if not elastic and values.get("dt") is not None and values.get("solver") != "fd":
        unused.append("dt")                       # the exact solver has no step
    if not unused:
        return ""
    model = "elastic model" if elastic else (
        "rigid model's fd scheme" if values.get("solver") == "fd" else "rigid exact solver")
    if isinstance(choice, bool):
        reads = (", ".join(_ELASTIC_ONLY) if elastic else
                 "solver, and dt with solver = \"fd\"")
        key = unused[0]
        raise UserError(key=f"[model] {key}", value=values[key],
                        allowed=f"none with elastic = {str(choice).lower()}: the {model} does "
                                f"not read it (of [model] it reads {reads})")
    return f"; [model] {', '.join(unused)} unused by the {model}"
