"""Momentum equation, pressure part (seed eq. 8).

    dv_a/dt = - sum_b m_b (P_a / rho_a^2 + P_b / rho_b^2) grad_a W_ab

Monaghan (1992) eq. 3.3: the symmetric form, which conserves linear and angular
momentum exactly because every pair contributes equal and opposite forces.
Fluid neighbours only by default (see :mod:`taisph.terms.continuity`);
``walls=True`` includes wall particles, for wall models whose particles carry a
pressure and density (dummy walls, :class:`taisph.terms.AdamiWall`).
"""

import taichi as ti

from .base import Term


@ti.data_oriented
class PressureGradient(Term):
    name = "pressure"
    scalars = ("p_over_rho2",)

    takes_walls = True

    @ti.func
    def derive(self, s: ti.template(), i):
        # P / rho^2 once per particle instead of a division per pair
        rho = s.Ss[self.q.density, i]
        s.Ss[self.q.p_over_rho2, i] = s.Ss[self.q.pressure, i] / (rho * rho)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        if self.sees(s, j):
            q = ti.static(self.q)
            pij = s.Ss[q.p_over_rho2, i] + s.Ss[q.p_over_rho2, j]
            rates.acc -= s.Ss[q.mass, j] * pij * grad
