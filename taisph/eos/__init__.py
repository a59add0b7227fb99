"""Equations of state: pressure (and sound speed) from density, per material.

Not terms: every scene has exactly one, evaluated for every particle when the state
is gathered in cell order, before any neighbour sum (see :mod:`taisph.engine.assembly`).
"""

from . import ideal_gas, tait
from .ideal_gas import IdealGas
from .tait import Tait

__all__ = ["Tait", "IdealGas", "tait", "ideal_gas"]
