"""Physical terms, one per module. See :mod:`taisph.terms.base` for the contract."""

from .adami_wall import AdamiWall
from .artificial_viscosity import ArtificialViscosity
from .base import NeighbourPass, Term
from .continuity import Continuity
from .density_diffusion import DensityDiffusion
from .gravity import Gravity
from .laminar_viscosity import LaminarViscosity
from .lennard_jones import LennardJonesWall
from .particle_shifting import ParticleShifting
from .pressure_gradient import PressureGradient
from .summation_density import SummationDensity
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
    "AdamiWall",
    "LaminarViscosity",
    "DensityDiffusion",
    "ParticleShifting",
]
