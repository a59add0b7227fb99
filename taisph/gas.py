"""Gas dynamics: the effects of compressible flow of an ideal gas, assembled from flags.

    import taisph
    from taisph import gas
    scene = taisph.Scene(..., eos=gas.IdealGas(), materials=[taisph.Gas(gamma=1.4)],
                         terms=gas.effects(density="summation", conductivity=True, variable_h=True))
    scene.add_fluid(points, mass=m, density=rho, energy=gas.energy(p, rho, 1.4))

The set (each a term in ``taisph/terms/``):

- density by summation (:class:`SummationDensity`) or by the continuity equation;
- the symmetric pressure force (:class:`PressureGradient`);
- the internal energy equation (:class:`InternalEnergy`, seed eq. 11);
- Monaghan's artificial viscosity with the quadratic beta term on
  (:class:`ArtificialViscosity`; alpha = 1, beta = 2), which heats the gas;
- optionally Price's artificial conductivity (:class:`ArtificialConductivity`);
- optionally a variable smoothing length h = eta (m/rho)^(1/dim)
  (:class:`AdaptiveSmoothingLength`).

:func:`cfl_dt` gives a fixed time step from the initial state.
"""

from __future__ import annotations

import numpy as np

from .eos import IdealGas
from .terms import (AdaptiveSmoothingLength, ArtificialConductivity, ArtificialViscosity, Continuity,
                    InternalEnergy, PressureGradient, SummationDensity)
from .eos.ideal_gas import energy, pressure, sound_speed

__all__ = ["effects", "cfl_dt", "IdealGas", "energy", "pressure", "sound_speed", "DENSITY"]

DENSITY = ("summation", "continuity")


def effects(density: str = "summation", conductivity: bool = True, variable_h: bool = True,
            alpha: float = 1.0, beta: float = 2.0, alpha_u: float = 1.0, h_factor: float = 1.2,
            energy_form: str = "compatible") -> list:
    """The terms of SPH gas dynamics (see the module docstring)."""
    if density not in DENSITY:
        raise ValueError(f"density must be one of {', '.join(DENSITY)}, got {density!r}")
    terms = [SummationDensity() if density == "summation" else Continuity()]
    if variable_h:
        terms.append(AdaptiveSmoothingLength(h_factor=h_factor))
    terms += [PressureGradient(), InternalEnergy(form=energy_form), ArtificialViscosity(alpha=alpha, beta=beta)]
    if conductivity:
        terms.append(ArtificialConductivity(alpha_u=alpha_u))
    return terms


def cfl_dt(scene, courant: float = 0.2) -> float:
    """A fixed time step dt = courant h_min / (c_max + |v|_max) from the initial state:
    c_max the largest initial sound speed sqrt(gamma p / rho), h_min the smallest
    initial smoothing length.

    The initial state does not show the faster signals a shock brings (Monaghan's 1992
    condition dt = 0.3 h / (c + 1.2 (alpha c + beta max mu)) counts the viscosity's
    too; in the Sod tube the post-shock u* + c* is 1.6 c_max(0)), hence a margin:
    the Sod tube (pc integrator) runs stably up to courant = 0.5 and blows up at 0.6,
    and its errors at 0.2 equal those at 0.05 to 1 % (docs/gas.md)."""
    c = scene.eos.max_sound_speed(scene)
    v = float(np.max(np.linalg.norm(scene.velocity, axis=1), initial=0.0))
    return courant * scene.smallest_smoothing_length() / (c + v)
