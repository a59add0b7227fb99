"""Monaghan artificial viscosity (seed eqs. 9-10).

    dv_a/dt += - sum_b m_b Pi_ab grad_a W_ab,

    Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab   if v_ab . r_ab < 0, else 0,
    mu_ab = h v_ab . r_ab / (r_ab^2 + eta^2),  eta^2 = 0.01 h^2,

with c_ab and rho_ab the pair means of sound speed and density (and h_ab the pair mean
of the smoothing lengths when they vary). Monaghan (1992) eq. 4.1-4.2; Monaghan (1994)
p. 400. The seed's eq. 10 omits c_ab; it is required for alpha to be dimensionless, as
in Monaghan's papers. Fluid neighbours only by default; ``walls=True`` includes the
particles of dummy walls (:class:`taisph.terms.AdamiWall`) with the density it gives
them and its no-slip wall velocity, as Adami et al. (2012) treat the viscous term at
walls. Then the wall exerts a numerical friction on fluid sliding along it, of the
order of the artificial kinematic viscosity nu_art = alpha h c0 / 8 (2D; Monaghan
2005 sec. 4.6), which shrinks with h: a friction of numerical origin, not water's
(see docs/accuracy.md, dam break).

When the scene evolves internal energy (:class:`taisph.terms.InternalEnergy`), the
viscosity also heats the gas by the work it takes from the motion,

    de_a/dt += 1/2 sum_b m_b Pi_ab (v_a - v_b) . grad_a W_ab,

so that the kinetic energy it dissipates becomes heat and total energy is conserved
(pair by pair, with the compatible energy equation). For shocks in a gas use
alpha ~ 1 and beta ~ 2; for liquids beta = 0 and a small alpha.
"""

import taichi as ti

from ..engine.layout import FLUID
from .base import Term


@ti.data_oriented
class ArtificialViscosity(Term):
    """Parameters: ``alpha`` (linear, shear/bulk viscosity), ``beta`` (quadratic,
    for shocks; 0 for liquids), ``eta_factor`` (eta^2 = eta_factor h^2, 0.01)."""

    name = "artificial_viscosity"
    params = {"alpha": 0.1, "beta": 0.0, "eta_factor": 0.01}

    takes_walls = True

    def bound(self, *args, **kwargs):
        t = super().bound(*args, **kwargs)
        t.heats = "d_energy" in t.r._fields  # compile-time: is internal energy evolved?
        return t

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if self.sees(s, j):
            vj = s.Sv[q.velocity, j]
            if ti.static(self.with_walls):
                if s.Si[q.kind, j] != FLUID:
                    vj = s.Sv[q.wall_velocity, j]
            vij = s.Sv[q.velocity, i] - vj
            vr = vij.dot(rij)
            if vr < 0.0:
                h = self.h_pair(s, i, j)
                mu = h * vr / (r * r + s.params[self.p.eta_factor] * h * h)
                c_ab = 0.5 * (self.eos.sound_speed(s, i) + self.eos.sound_speed(s, j))
                rho_ab = 0.5 * (s.Ss[q.density, i] + s.Ss[q.density, j])
                pi_ab = (-s.params[self.p.alpha] * c_ab * mu + s.params[self.p.beta] * mu * mu) / rho_ab
                rates.acc -= s.Ss[q.mass, j] * pi_ab * grad
                if ti.static(self.heats):
                    rates.d[self.r.d_energy] += 0.5 * s.Ss[q.mass, j] * pi_ab * vij.dot(grad)
