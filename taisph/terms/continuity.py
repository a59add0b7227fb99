"""Continuity equation: density evolved in time (seed eq. 7).

    d rho_a / dt = sum_b m_b (v_a - v_b) . grad_a W_ab

Monaghan (1992) eq. 3.8; Monaghan (1994) eq. 2.4. Only fluid neighbours contribute:
wall particles of the Lennard-Jones kind act on the fluid by a force, not through
the SPH sums (seed section 2). ``walls=True`` includes wall particles with their own
(prescribed) velocity, for dummy walls (:class:`taisph.terms.AdamiWall`).
"""

import taichi as ti

from .base import Term


@ti.data_oriented
class Continuity(Term):
    name = "continuity"
    integrates = {"density": "d_density"}

    takes_walls = True

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        if self.sees(s, j):
            vij = s.Sv[self.q.velocity, i] - s.Sv[self.q.velocity, j]
            rates.d[self.r.d_density] += s.Ss[self.q.mass, j] * vij.dot(grad)
