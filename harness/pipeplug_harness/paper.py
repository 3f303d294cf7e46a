"""The paper's constants and the name mappings, in one place.

* The paper's blow (section 3): :data:`Q0` [N] for :data:`T0` [s]; its Fig. 7 is observed to
  :data:`T_FIG7` [s].
* Parameter names: :data:`RIGID_PARAMETERS` (models I and II), taken from the core's one
  parameter table, not retyped, less the ram at the head (:data:`RAM_PARAMETERS`) and the
  soil's end resistance (:data:`FACE_PARAMETERS`) and the clean-out (:data:`GROWTH_PARAMETERS`),
  which the paper's models and their closed form do not have.
* Output names: the core's outputs (``v_pipe``, ...) against the paper's and the closed form's
  symbols (``V1``, ...): :data:`SYMBOLS`, :func:`to_symbols`.
* Units of the outputs: :data:`OUTPUT_UNITS`, from the core's output table.
"""
from __future__ import annotations

import numpy as np

from pipeplug import OUTPUTS, PARAMETERS

__all__ = ["Q0", "T0", "T_FIG7", "RAM_PARAMETERS", "FACE_PARAMETERS", "GROWTH_PARAMETERS",
           "RIGID_PARAMETERS",
           "PARAMETER_UNITS", "OUTPUT_UNITS", "SYMBOLS", "MOTION", "to_symbols", "rigid_values"]

#: The paper's blow: amplitude [N] and duration [s] (section 3, every figure).
Q0, T0 = 23000.0, 0.05
#: The end of the paper's Fig. 7 [s].
T_FIG7 = 0.08

#: The ram at the head and its cushion: the core's, not the paper's (0 mass: no ram).
RAM_PARAMETERS: tuple[str, ...] = ("ram_mass", "cushion_stiffness", "cushion_restitution")
#: The soil's end resistance: the core's, not the paper's (0: none).
FACE_PARAMETERS: tuple[str, ...] = ("q_face", "q_plug_face")
#: Smith damping: the core's, not the paper's (0: none).
DAMPING_PARAMETERS: tuple[str, ...] = ("J_shaft", "J_face")
#: The clean-out of a plug that grows: the core's, not the paper's.
GROWTH_PARAMETERS: tuple[str, ...] = ("L2_after_cleanout",)
#: The core's effects beyond the paper, each absent at its default.
EFFECT_PARAMETERS = RAM_PARAMETERS + FACE_PARAMETERS + DAMPING_PARAMETERS + GROWTH_PARAMETERS
#: Parameters of the paper's rigid models I and II (the physical ones no model option switches
#: on, the effects beyond the paper left out).
RIGID_PARAMETERS: tuple[str, ...] = tuple(p.name for p in PARAMETERS
                                          if p.active_with is None and p.unit != "1"
                                          and p.name not in EFFECT_PARAMETERS)
#: parameter -> its SI unit (the core's table)
PARAMETER_UNITS: dict[str, str] = {p.name: p.unit for p in PARAMETERS}
#: output -> its SI unit (the core's table; "1" for the modes and the flag)
OUTPUT_UNITS: dict[str, str] = {o.name: o.unit for o in OUTPUTS}

#: core output name -> the paper's symbol (and the closed form's column)
SYMBOLS = {"v_pipe": "V1", "v_plug": "V2", "u_pipe": "U1", "u_plug": "U2"}
#: the outputs every motion comparison uses (velocities, then displacements)
MOTION = tuple(SYMBOLS)


def to_symbols(columns) -> dict:
    """Core output columns (``v_pipe``, ...) as the paper's symbols (``V1``, ...), float arrays."""
    return {symbol: np.asarray(columns[name], dtype=float) for name, symbol in SYMBOLS.items()}


def rigid_values(source) -> dict:
    """The rigid parameters of ``source`` (an object with them as attributes, e.g. a closed
    form case or the core's Params) by name."""
    return {name: getattr(source, name) for name in RIGID_PARAMETERS}
