"""Physical terms, one per module. See :mod:`taisph.terms.base` for the contract."""

from .adami_wall import AdamiWall
from .artificial_conductivity import ArtificialConductivity
from .artificial_viscosity import ArtificialViscosity
from .base import NeighbourPass, Term, VolumeTerm
from .continuity import Continuity
from .continuity_colagrossi import ContinuityColagrossi
from .damping_zone import DampingZone
from .density_diffusion import DensityDiffusion
from .density_relaxation import DensityRelaxation
from .drain import Drain
from .energy import InternalEnergy
from .gravity import STANDARD_GRAVITY, Gravity
from .laminar_viscosity import LaminarViscosity
from .lennard_jones import LennardJonesWall
from .particle_shifting import ParticleShifting
from .pressure_gradient import PressureGradient
from .smoothing_length import AdaptiveSmoothingLength
from .summation_density import SummationDensity
from .pressure_hu_adams import PressureHuAdams
from .phase_viscosity import PhaseViscosity
from .surface_tension import SurfaceTension
from .riemann import Riemann
from .xsph import XSPH
from .open_boundary import OpenBoundaries  # made by Scene.add_open_boundary, not listed by hand
from .rigid_bodies import RigidBodies  # made by Scene.add_body, not listed by hand

__all__ = [
    "Term",
    "NeighbourPass",
    "VolumeTerm",
    "Gravity",
    "STANDARD_GRAVITY",
    "Continuity",
    "PressureGradient",
    "ArtificialViscosity",
    "LennardJonesWall",
    "SummationDensity",
    "XSPH",
    "ContinuityColagrossi",
    "PressureHuAdams",
    "PhaseViscosity",
    "SurfaceTension",
    "InternalEnergy",
    "ArtificialConductivity",
    "AdaptiveSmoothingLength",
    "AdamiWall",
    "LaminarViscosity",
    "DensityDiffusion",
    "DensityRelaxation",
    "ParticleShifting",
    "Riemann",
    "DampingZone",
    "Drain",
    "OpenBoundaries",
    "RigidBodies",
]
