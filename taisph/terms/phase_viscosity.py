"""Physical viscosity with a viscosity per material: the multiphase form of Hu & Adams (2006).

    dv_i/dt += (1/m_i) sum_j  2 mu_i mu_j / (mu_i + mu_j)  (V_i^2 + V_j^2)
                              (r_ij . grad_i W_ij) / (r_ij^2 + eta^2)  v_ij,

mu the dynamic viscosity of each particle's material (``Material.viscosity``, Pa s),
V = m / rho the particle volume, r_ij = x_i - x_j, v_ij = v_i - v_j, eta^2 = 0.01 h^2.
X. Y. Hu and N. A. Adams, J. Comput. Phys. 213:844 (2006), eq. 9 (the inter-particle
viscosity, the harmonic mean, keeps the shear stress continuous across an interface
between fluids of different viscosity); also Adami, Hu & Adams (2010), J. Comput. Phys.
229:5011, eq. 7. For one fluid (equal mu, rho and m) it is exactly Morris, Fox & Zhu's
laminar viscosity (:class:`taisph.terms.LaminarViscosity`) with nu = mu / rho. Pairs are
equal and opposite: linear momentum is conserved.

Volumes, not masses: a water particle beside an air particle 1000 times lighter feels
the air's shear through the air's volume and viscosity, so neither phase's viscous
force carries the other's density scale.

``walls=True`` adds dummy wall particles (:class:`taisph.terms.AdamiWall`) with the
no-slip velocity extrapolated from the fluid (Adami, Hu & Adams 2012 eq. 23) and the
fluid particle's own viscosity (the wall takes the phase beside it). Without walls they
exert no shear (free slip).

The time step: dt <= C_visc h^2 / max_k (mu_k / rho0_k) over the materials (Morris et
al. 1997 eq. 19; C_visc the ``viscous_factor`` control, 0.125).
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .base import VolumeTerm


@ti.data_oriented
class PhaseViscosity(VolumeTerm):
    name = "phase_viscosity"
    takes_walls = True
    material_columns = ("viscosity",)

    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        t.p_viscous_factor = param_rows["viscous_factor"]
        return t

    def check(self, scene):
        if not any(m.viscosity > 0 for m in scene.materials):
            raise InputError("phase_viscosity: every material has viscosity 0; give the materials their dynamic "
                             "viscosity (Material(..., viscosity=MU) in Pa s, or 'viscosity' in [[materials]])")
        if "laminar_viscosity" in scene.terms_by_name:
            raise InputError("use either LaminarViscosity (one nu) or PhaseViscosity (a viscosity per material), "
                             "not both")
        super().check(scene)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if self.sees(s, j):
            mu_i = s.mat[s.Si[q.material, i], self.m.viscosity]
            mu_j = mu_i  # a wall takes the viscosity of the phase beside it
            vj = s.Sv[q.velocity, j]
            if s.Si[q.kind, j] == FLUID:
                mu_j = s.mat[s.Si[q.material, j], self.m.viscosity]
            elif ti.static(self.with_walls):
                vj = s.Sv[q.wall_velocity, j]
            mu_ij = 2.0 * mu_i * mu_j / ti.max(mu_i + mu_j, 1e-30)
            v_i = s.Ss[q.volume, i]
            v_j = s.Ss[q.volume, j]
            h = s.params[self.p_h]
            f = mu_ij * (v_i * v_i + v_j * v_j) / s.Ss[q.mass, i] * rij.dot(grad) / (r * r + 0.01 * h * h)
            rates.acc += f * (s.Sv[q.velocity, i] - vj)

    @ti.func
    def step_limit(self, s: ti.template()):
        nu = ti.cast(0.0, ti.f64)
        for k in range(self.material_count(s)):
            nu = ti.max(nu, ti.cast(s.mat[k, self.m.viscosity] / s.mat[k, self.m.rho0], ti.f64))
        return viscous_limit_device(ti.cast(s.params[self.p_h], ti.f64), nu,
                                    ti.cast(s.params[self.p_viscous_factor], ti.f64))

    def host_step_limit(self, scene, controls) -> float:
        nu = max(m.viscosity / m.rho0 for m in scene.materials)
        return float(viscous_limit(scene.smoothing_length, nu, controls.viscous_factor))


def viscous_limit(h, nu, factor):
    """C_visc h^2 / nu (no limit, 1e300 s, for nu = 0); Python numbers or, in a kernel, f64 values."""
    return factor * h * h / ti.max(nu, 1e-300)


viscous_limit_device = ti.func(viscous_limit)
