"""Laminar (physical) viscosity, Morris, Fox & Zhu (1997) eq. 8.

    dv_a/dt += sum_b m_b (mu_a + mu_b) r_ab . grad_a W_ab / (rho_a rho_b (r_ab^2 + eta^2)) v_ab,

with mu = rho nu (``nu``: kinematic viscosity, m^2/s), r_ab = x_a - x_b, v_ab = v_a - v_b
and eta^2 = 0.01 h^2. It is the SPH Laplacian of Brookshaw (1985) applied to velocity:
a first-derivative kernel gradient replaces the second derivative, so it is accurate
on disordered particles and conserves linear momentum (pairs are equal and opposite).

``walls=True`` adds wall particles as neighbours with the no-slip velocity that the
dummy-wall term (:class:`taisph.terms.AdamiWall`) extrapolates from the fluid,
v_w = 2 v_wall - sum_f v_f W_wf / sum_f W_wf (Adami, Hu & Adams 2012 eqs. 22-23), and
the wall density it sets from the wall pressure. Without it walls exert no shear
(free slip).
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .base import Term


@ti.data_oriented
class LaminarViscosity(Term):
    name = "laminar_viscosity"
    params = {"nu": None}

    takes_walls = True
    viscosity_param = "nu"  # limits dt to 0.125 h^2 / nu

    def check(self, scene):
        nu = self.values.get("nu")
        if nu is None or not nu >= 0:
            raise InputError(f"LaminarViscosity needs a kinematic viscosity nu >= 0 (m^2/s), got {nu!r}")
        super().check(scene)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if self.sees(s, j):
            vj = s.Sv[q.velocity, j]
            if ti.static(self.with_walls):
                if s.Si[q.kind, j] != FLUID:
                    vj = s.Sv[q.wall_velocity, j]
            rho_i = s.Ss[q.density, i]
            rho_j = s.Ss[q.density, j]
            h = s.params[self.p_h]
            f = (s.params[self.p.nu] * s.Ss[q.mass, j] * (rho_i + rho_j) / (rho_i * rho_j)
                 * rij.dot(grad) / (r * r + 0.01 * h * h))
            rates.acc += f * (s.Sv[q.velocity, i] - vj)
