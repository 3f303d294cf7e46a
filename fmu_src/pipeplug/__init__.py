"""PipePlug: percussive pipe ramming with a soil plug and Coulomb dry friction.

The pure numeric core (numpy only; numba optional): rigid models I and II with an exact
event-driven solver and the paper's explicit scheme, and the elastic model III. See
:func:`build_model` and :mod:`pipeplug.interface`.
"""
from .factory import build_model
from .interface import OUTPUT_NAMES, OUTPUTS, Model, Output, Outputs
from .options import OPTIONS, Options
from .params import PARAMETERS, ParameterError, Params
from .state import state_from_bytes, state_to_bytes

__all__ = ["build_model", "Model", "Output", "Outputs", "OUTPUTS", "OUTPUT_NAMES", "Options",
           "OPTIONS", "Params", "PARAMETERS", "ParameterError", "state_to_bytes",
           "state_from_bytes"]
__version__ = "0.2.0"
