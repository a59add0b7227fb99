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

A fixed time step from the initial state: :func:`taisph.engine.timestep.initial_dt`
(the gas cases use courant = 0.2: shocks raise the signal speed above its initial value).
"""

from __future__ import annotations

from ..eos import IdealGas
from ..terms import (AdaptiveSmoothingLength, ArtificialConductivity, ArtificialViscosity, Continuity,
                     InternalEnergy, PressureGradient, SummationDensity)
from ..eos.ideal_gas import energy, pressure, sound_speed
from ..messages import InputError

__all__ = ["effects", "IdealGas", "energy", "pressure", "sound_speed", "DENSITY"]

DENSITY = ("summation", "continuity")


def effects(density: str = "summation", conductivity: bool = True, variable_h: bool = True,
            alpha: float = 1.0, beta: float = 2.0, alpha_u: float = 1.0, h_factor: float = 1.2,
            energy_form: str = "compatible") -> list:
    """The terms of SPH gas dynamics (see the module docstring)."""
    if density not in DENSITY:
        raise InputError(f"density must be one of {', '.join(DENSITY)}, got {density!r}")
    terms = [SummationDensity() if density == "summation" else Continuity()]
    if variable_h:
        terms.append(AdaptiveSmoothingLength(h_factor=h_factor))
    terms += [PressureGradient(), InternalEnergy(form=energy_form), ArtificialViscosity(alpha=alpha, beta=beta)]
    if conductivity:
        terms.append(ArtificialConductivity(alpha_u=alpha_u))
    return terms

