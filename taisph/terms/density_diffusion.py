"""Density diffusion (delta-SPH), Molteni & Colagrossi (2009), with a hydrostatic
correction after Fourtakas et al. (2019).

    d rho_a/dt += 2 delta h c0 sum_b (rho_a - rho_b - rho^H_ab) (r_ab . grad_a W_ab) / (r_ab^2 + eta^2) m_b / rho_b

with r_ab = x_a - x_b, eta^2 = 0.01 h^2, c0 the material's sound speed and ``delta``
(0.1 in Molteni & Colagrossi and Antuono et al. 2010). It is a Laplacian of density,
sum_b 2 (r.grad W)/r^2 ~ nabla^2: it damps the high-frequency density (and so
pressure) noise of weakly compressible SPH, at a cost of O(h) numerical diffusion.

Plain diffusion of density is wrong where density has a physical gradient: in a fluid
at rest under gravity it moves mass from the bottom up until the hydrostatic density
profile is flattened (Antuono et al. 2010 remove this with a renormalised density
gradient, which needs an extra neighbour pass and a matrix inversion per particle).
taisph subtracts the hydrostatic part of the density difference instead, as Fourtakas,
Dominguez, Vacondio & Rogers (2019, Comput. Fluids 190:346) do:

    rho^H_ab = rho_H,a - rho_H,b = rho_ab g . r_ab / c_ab^2,    c^2 = dp/drho = gamma (P + B) / rho,

the density difference of a fluid in hydrostatic equilibrium, dp = rho g . dx, with the
Tait sound speed at the pair's mean density and pressure (Fourtakas et al. use
rho0 [(1 + rho0 g z_ab / B)^(1/gamma) - 1], which agrees to first order; ours is exact
for the Tait hydrostatic profile to second order in r_ab). ``hydrostatic=False`` drops
it (for flows without gravity the two are identical). ``g`` is the ``gravity``
parameter of the scene's :class:`Gravity` term.

Fluid neighbours only, as in the original formulation (wall particles carry no
physical density gradient). Needs the continuity equation (it adds to its rate).
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .hydrostatic import head as hydrostatic_head
from .base import Term


@ti.data_oriented
class DensityDiffusion(Term):
    name = "density_diffusion"
    params = {"delta": 0.1}
    wall_range = None  # fluid neighbours only

    def __init__(self, hydrostatic: bool = True, **values):
        super().__init__(**values)
        self.options = {"hydrostatic": bool(hydrostatic)}

    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        t.p_gravity = param_rows.get("gravity") if self.options["hydrostatic"] else None
        t.has_gravity = t.p_gravity is not None
        return t

    def check(self, scene):
        if not any(t.integrates.get("density") == "d_density" for t in scene.terms):
            raise InputError("density_diffusion needs the continuity equation (Continuity) in the scene")
        if not self.values["delta"] >= 0:
            raise InputError(f"density_diffusion: delta must be >= 0, got {self.values['delta']!r}")

    def describe(self):
        return super().describe()[:-1] + (", hydrostatic correction)" if self.options["hydrostatic"] else ")")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        m = ti.static(self.m)
        if s.Si[q.kind, j] == FLUID:
            rho_i = s.Ss[q.density, i]
            rho_j = s.Ss[q.density, j]
            material = s.Si[q.material, i]
            drho = rho_i - rho_j
            if ti.static(self.has_gravity):
                rho_m = 0.5 * (rho_i + rho_j)
                p_m = 0.5 * (s.Ss[q.pressure, i] + s.Ss[q.pressure, j])
                c2 = s.mat[material, m.gamma] * (p_m + s.mat[material, m.B]) / rho_m
                drho -= rho_m * hydrostatic_head(s, self.p_gravity, rij) / c2
            h = s.params[self.p_h]
            coeff = 2.0 * s.params[self.p.delta] * h * s.mat[material, m.c0]
            rates.d[self.r.d_density] += (coeff * drho * rij.dot(grad) / (r * r + 0.01 * h * h)
                                          * s.Ss[q.mass, j] / rho_j)
