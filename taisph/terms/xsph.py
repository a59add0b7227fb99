"""XSPH: particles move with a locally averaged velocity (Monaghan 1989; 1994 eq. 2.6).

    dx_a/dt = v_a + eps sum_b (m_b / rho_ab) (v_b - v_a) W_ab,   rho_ab = (rho_a + rho_b)/2

The correction (``rates.shift``) changes where particles go, not their momentum: the
momentum equation still advances v_a. eps = 0.5 in Monaghan (1994). It keeps particles
more ordered in high-speed flows at the price of some numerical dissipation of
relative motion. Fluid neighbours only.
"""

import taichi as ti

from ..engine.layout import FLUID
from .base import Term


@ti.data_oriented
class XSPH(Term):
    name = "xsph"
    params = {"xsph_eps": 0.5}
    wall_range = None  # fluid neighbours only
    has_shift = True

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] == FLUID:
            rho_ab = 0.5 * (s.Ss[q.density, i] + s.Ss[q.density, j])
            weight = s.params[self.p.xsph_eps] * s.Ss[q.mass, j] / rho_ab * self.w(s, r)
            rates.shift += weight * (s.Sv[q.velocity, j] - s.Sv[q.velocity, i])
