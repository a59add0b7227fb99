"""Tait (Cole) equation of state for weakly compressible liquids (seed eq. 12).

    P = B [ (rho / rho0)^gamma - 1 ] + p_b,    B = rho0 c0^2 / gamma,

Monaghan (1994) eq. 3.1 / Batchelor (1967). gamma = 7 for water. The sound speed c0
sets the compressibility: c0 >= 10 U_max keeps density variations near 1 %.
Each material has its own rho0, c0, gamma (columns of the material table), and its
own background pressure p_b (``Material.background_pressure``, 0 by default: the seed's
form). A background pressure, the same in every phase, is what lets two phases of very
different density share a closed box (Colagrossi & Landrini 2003 sec. 3; Adami, Hu &
Adams 2010 eq. 11): the pressure stays positive everywhere, so the light phase is never
stretched into the tensile instability, and the momentum equation's non-conservative
volume form turns the uniform p_b into a force that keeps particles evenly spaced
(docs/multiphase.md). It adds nothing where p_b = 0 (x + 0.0 is x: the seed's runs
are unchanged to the bit).

``Tait(tension=False)``: a liquid that cannot be stretched. A particle whose density
falls below rho0 is separating from its neighbours (a breaking jet, spray, a
splash): its density is held at rho0, so it flies with zero pressure and feels
pressure again as soon as it is compressed, rho <- max(rho, rho0), P >= 0.
With tension (the default, the seed's model) a stretched jet has P down to -B: that
pulls thin ligaments into clumps that fly apart at tens of m/s, the tensile
instability of free-surface SPH (Swegle et al. 1995; Sun et al. 2017). Flooring
only the pressure is not enough with the continuity equation: a particle that flew
as spray keeps its low density and lands as a hole the bulk collapses into
(docs/stability.md). SPlisHSPlasH's WCSPH clamps its density the same way (Becker &
Teschner 2007). The density guard then checks compression only.
"""

import copy

import numpy as np
import taichi as ti


@ti.data_oriented
class Tait:
    """The equation of state a scene uses; the solver calls :meth:`derive` for every
    particle when it gathers the state in cell order, before the rates are summed."""

    name = "tait"
    columns = ("rho0", "c0", "gamma", "B", "p_b")  # per-material constants (material table)
    scalars = ("sound_speed",)  # per-particle quantities it stores
    derived = ("sound_speed",)  # ... recomputed from the state every step (not carried)
    outputs = ()  # stored quantities worth writing to the frames
    tension = True  # class default (the instance sets its own in __init__)

    def __init__(self, tension: bool = True):
        self.tension = bool(tension)

    def __repr__(self):
        return "Tait()" if self.tension else "Tait(tension=False)"

    def material_row(self, material) -> list:
        b = material.rho0 * material.c0**2 / material.gamma
        return [material.rho0, material.c0, material.gamma, b, getattr(material, "background_pressure", 0.0)]

    def bind(self, layout, material_cols):
        """A copy with compile-time rows attached (the scene's own stays picklable)."""
        bound = copy.copy(self)
        bound.q = layout.q
        bound.m = material_cols
        return bound

    def compile_key(self):
        return ("tait",) if self.tension else ("tait", "no tension")

    @ti.func
    def derive(self, s: ti.template(), i):
        """Pressure and sound speed of (sorted) particle i from its density."""
        q = ti.static(self.q)
        material = s.Si[q.material, i]
        rho = s.Ss[q.density, i]
        if ti.static(not self.tension):  # a liquid is not stretched: no density below rho0
            rho = ti.max(rho, s.mat[material, self.m.rho0])
            s.Ss[q.density, i] = rho
        s.Ss[q.pressure, i] = self.pressure(s, material, rho)
        s.Ss[q.sound_speed, i] = s.mat[material, self.m.c0]

    @ti.func
    def pressure(self, s: ti.template(), material, rho):
        ratio = rho / s.mat[material, self.m.rho0]
        gamma = s.mat[material, self.m.gamma]
        power = 0.0
        if gamma == 7.0:  # water: 4 multiplications instead of a libm pow (docs/performance.md)
            r2 = ratio * ratio
            power = r2 * r2 * r2 * ratio
        else:
            power = ti.pow(ratio, gamma)
        return s.mat[material, self.m.B] * (power - 1.0) + s.mat[material, self.m.p_b]

    @ti.func
    def density_at(self, s: ti.template(), material, p):
        """Inverse Tait on the device: the density at pressure p, rho0 (1 + (p - p_b) / B)^(1/gamma).
        The base is floored at 0.05 (a pressure below p_b - 0.95 B, as an extrapolation far
        into tension can give, would have no real root)."""
        base = ti.max(1.0 + (p - s.mat[material, self.m.p_b]) / s.mat[material, self.m.B], 0.05)
        return s.mat[material, self.m.rho0] * ti.pow(base, 1.0 / s.mat[material, self.m.gamma])

    @ti.func
    def sound_speed(self, s: ti.template(), i):
        return s.Ss[self.q.sound_speed, i]


def pressure(rho, rho0, c0, gamma=7.0, tension=True, background_pressure=0.0):
    """Tait pressure (numpy), for initial conditions and tests."""
    p = rho0 * c0**2 / gamma * ((rho / rho0) ** gamma - 1.0)
    return (p if tension else np.maximum(p, 0.0)) + background_pressure


def density(p, rho0, c0, gamma=7.0, background_pressure=0.0):
    """Inverse Tait: the density at pressure p (numpy)."""
    return rho0 * (1.0 + (p - background_pressure) * gamma / (rho0 * c0**2)) ** (1.0 / gamma)
