"""PipePlug: percussive pipe ramming with a soil plug and Coulomb dry friction.

The pure numeric core (numpy only): rigid models I and II with an exact event-driven solver
and the paper's explicit scheme, and the elastic model III. See :func:`build_model`.
"""
from .model import OUTPUT_NAMES, Model, Outputs, build_model
from .options import OPTIONS, Options
from .params import PARAMETERS, ParameterError, Params
from .state import state_from_bytes, state_to_bytes

__all__ = ["build_model", "Model", "Outputs", "OUTPUT_NAMES", "Options", "OPTIONS", "Params",
           "PARAMETERS", "ParameterError", "state_to_bytes", "state_from_bytes"]
__version__ = "0.1.0"
