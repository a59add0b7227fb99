"""Two phases in one scene: the terms that carry them and the state they start in.

The formulation (docs/multiphase.md): momentum, viscosity and surface stress in the
volume forms of Hu & Adams (2006) (:class:`taisph.terms.PressureHuAdams`,
:class:`taisph.terms.PhaseViscosity`, :class:`taisph.terms.SurfaceTension`),
continuity in the form of Colagrossi & Landrini (2003)
(:class:`taisph.terms.ContinuityColagrossi`), each material with its own rho0, c0,
viscosity and a background pressure shared by all (:class:`taisph.scene.Material`),
dummy walls (Adami, Hu & Adams 2012) where there are walls.
"""

import numpy as np

from ..eos import tait
from ..terms import AdamiWall, ContinuityColagrossi, Gravity, PhaseViscosity, PressureHuAdams, SurfaceTension


def two_phase_terms(sigma: float | None = None, walls: bool = True, gravity=None, viscous: bool = True) -> list:
    """The terms of a two-phase scene: continuity and pressure (Colagrossi & Landrini;
    Hu & Adams), a viscosity per material if `viscous`, surface tension if `sigma` is
    not None, gravity if given (a vector), and dummy walls if `walls`."""
    terms = [ContinuityColagrossi(walls=walls), PressureHuAdams(walls=walls)]
    if viscous:
        terms.append(PhaseViscosity(walls=walls))
    if sigma is not None:
        terms.append(SurfaceTension(sigma=sigma))
    if gravity is not None:
        terms.append(Gravity(gravity=tuple(gravity)))
    if walls:
        terms.append(AdamiWall(per_phase=True))
    return terms


def phase_densities(material, pressure) -> np.ndarray:
    """The density of `material` at `pressure` (Pa, an array): the inverse Tait equation
    with the material's background pressure."""
    return tait.density(np.asarray(pressure, float), material.rho0, material.c0, material.gamma,
                        material.background_pressure)
