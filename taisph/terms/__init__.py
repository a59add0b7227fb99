"""Physical terms, one per module. See :mod:`taisph.terms.base` for the contract."""

from .artificial_viscosity import ArtificialViscosity
from .base import NeighbourPass, Term
from .continuity import Continuity
from .continuity_colagrossi import ContinuityColagrossi
from .gravity import Gravity
from .lennard_jones import LennardJonesWall
from .pressure_gradient import PressureGradient
from .summation_density import SummationDensity
from .pressure_hu_adams import PressureHuAdams
from .tait import Tait
from .xsph import XSPH

__all__ = [
    "Term",
    "NeighbourPass",
    "Gravity",
    "Continuity",
    "PressureGradient",
    "ArtificialViscosity",
    "LennardJonesWall",
    "Tait",
    "SummationDensity",
    "XSPH",
    "ContinuityColagrossi",
    "PressureHuAdams",
]
