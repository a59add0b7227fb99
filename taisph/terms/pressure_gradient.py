"""Momentum equation, pressure part (seed eq. 8).

    dv_a/dt = - sum_b m_b (P_a / rho_a^2 + P_b / rho_b^2) grad_a W_ab

Monaghan (1992) eq. 3.3: the symmetric form, which conserves linear and angular
momentum exactly because every pair contributes equal and opposite forces.
Fluid neighbours only by default (see :mod:`taisph.terms.continuity`);
``walls=True`` includes wall particles, for wall models whose particles carry a
pressure and density (dummy walls, :class:`taisph.terms.AdamiWall`).
"""

import taichi as ti

from ..engine.layout import FLUID
from .base import Term


@ti.data_oriented
class PressureGradient(Term):
    name = "pressure"
    has_pair = True
    has_derive = True
    scalars = ("p_over_rho2",)

    def __init__(self, walls: bool = False):
        super().__init__()
        self.options = {"walls": bool(walls)}

    @property
    def wall_range(self):
        return "support" if self.options["walls"] else None

    def describe(self):
        return "pressure(walls)" if self.options["walls"] else "pressure"

    @ti.func
    def derive(self, s: ti.template(), i):
        # P / rho^2 once per particle instead of a division per pair
        rho = s.Ss[self.q.density, i]
        s.Ss[self.q.p_over_rho2, i] = s.Ss[self.q.pressure, i] / (rho * rho)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        if ti.static(self.options["walls"]) or s.Si[self.q.kind, j] == FLUID:
            q = ti.static(self.q)
            pij = s.Ss[q.p_over_rho2, i] + s.Ss[q.p_over_rho2, j]
            rates.acc -= s.Ss[q.mass, j] * pij * grad
