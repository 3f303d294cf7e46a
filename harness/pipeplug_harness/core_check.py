"""The FMU's start values checked by the core itself, before any run: a file's parameters and
options refused with the core's own words (the FMU would refuse them at initialization, after
the command had made its output folder)."""
from __future__ import annotations

from pipeplug_harness.session import split_start_values

__all__ = ["check_with_core", "params_of"]


def check_with_core(start_values: dict):
    """Build the core model from the start values, as the FMU does at initialization, so that
    every parameter and option is checked by the core's own rules before a run.

    Returns
    -------
    Params
        The validated parameters.

    Raises
    ------
    pipeplug.ParameterError
        Naming the offending parameter or option, its value and the allowed range.
    """
    from pipeplug import build_model
    from pipeplug.options import Options
    options = Options.from_mapping(split_start_values(start_values)[1])
    params = params_of(start_values)
    build_model(params, options)
    return params


def params_of(start_values: dict):
    """The core's Params from start values (options left out), not yet validated."""
    from pipeplug.params import Params
    return Params.from_mapping(split_start_values(start_values)[0])
