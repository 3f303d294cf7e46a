"""PipePlug.fmu's slave class (FMI 2.0): the slave on the FMI 2.0 binding."""
from __future__ import annotations

from .fmi2 import Fmi2Binding
from .slave import PipePlugSlave

__all__ = ["PipePlug"]


class PipePlug(PipePlugSlave, Fmi2Binding):
    pass
