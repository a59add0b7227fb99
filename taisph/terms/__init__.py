"""Physical terms, one per module. See :mod:`taisph.terms.base` for the contract."""

from .artificial_viscosity import ArtificialViscosity
from .base import Term
from .continuity import Continuity
from .continuity_colagrossi import ContinuityColagrossi
from .gravity import Gravity
from .lennard_jones import LennardJonesWall
from .pressure_gradient import PressureGradient
from .pressure_hu_adams import PressureHuAdams
from .tait import Tait

__all__ = [
    "Term",
    "Gravity",
    "Continuity",
    "PressureGradient",
    "ArtificialViscosity",
    "LennardJonesWall",
    "Tait",
    "ContinuityColagrossi",
    "PressureHuAdams",
]
