"""Hammer.fmu's slave class (FMI 2.0): the slave on the FMI 2.0 binding."""
from __future__ import annotations

from .fmi2 import Fmi2Binding
from .hammer import HammerSlave

__all__ = ["Hammer"]


class Hammer(HammerSlave, Fmi2Binding):
    pass
