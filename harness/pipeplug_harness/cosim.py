"""What every libcosim run of PipePlug.fmu (and Hammer.fmu) needs first: its start values
checked by the code the FMU runs.

libcosim calls ``std::terminate`` when any FMU of an execution fails
``fmi2ExitInitializationMode``: the whole process ends, with the FMU's one log line as the only
trace. Whatever builds a libcosim execution with PipePlug calls :func:`check_parameters` with
the start values first (and :func:`check_hammer_parameters` with a Hammer's), so an invalid one
is refused here, with the FMU's own wording, and no execution is built.
"""
from __future__ import annotations

from collections.abc import Mapping

__all__ = ["check_parameters", "check_hammer_parameters"]


def check_parameters(start_values: Mapping[str, object]) -> None:
    """Refuse start values that PipePlug.fmu would refuse at exitInitializationMode.

    Parameters
    ----------
    start_values : mapping
        FMU parameter and option names to start values (Reals in SI units, ``solver`` a
        string, ``contact_growth``/``elastic`` booleans); missing ones take their defaults.

    Raises
    ------
    pipeplug.ParameterError
        Naming the first refused variable, its value and the allowed range, as the FMU's log
        line does; also for a name that is not a parameter or option of the FMU.
    """
    from pipeplug import OPTIONS, PARAMETERS, Options, ParameterError, Params

    reals = {p.name for p in PARAMETERS}
    for name, value in start_values.items():
        if name not in reals and name not in OPTIONS:
            raise ParameterError(name, value, "a parameter or option of PipePlug: "
                                 + ", ".join([*sorted(reals), *OPTIONS]))
    options = Options.from_mapping({k: v for k, v in start_values.items() if k in OPTIONS})
    params = Params.from_mapping({k: _real(k, v) for k, v in start_values.items() if k in reals})
    params.validate(options.active_groups())


def _real(name: str, value: object) -> float:
    """``value`` as the FMI Real the FMU would receive."""
    from pipeplug import ParameterError

    try:
        return float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "a Real number") from None


def check_hammer_parameters(start_values: Mapping[str, object]) -> None:
    """Refuse start values that Hammer.fmu would refuse at exitInitializationMode.

    Parameters
    ----------
    start_values : mapping
        Hammer's parameter names to start values (``count`` an integer, the others Reals in SI
        units); missing ones take their defaults.

    Raises
    ------
    pipeplug.ParameterError
        Naming the first refused variable, its value and the allowed range, as the FMU's log
        line does (the check is the FMU's own, :func:`pipeplug_fmu.blows.check`); also for a
        name that is not a parameter of the FMU.
    """
    from pipeplug import ParameterError
    from pipeplug_fmu.blows import BlowTrainError, check

    try:
        check(start_values)
    except BlowTrainError as exc:
        raise ParameterError(exc.name, exc.value, exc.allowed) from None
