"""Continuity equation in the multiphase form of Colagrossi & Landrini (2003).

    d rho_i / dt = rho_i sum_j V_j (v_i - v_j) . grad_i W_ij,     V_j = m_j / rho_j,

A. Colagrossi and M. Landrini, "Numerical simulation of interfacial flows by smoothed
particle hydrodynamics", J. Comput. Phys. 191:448-475 (2003) (also used by Hu &
Adams 2006; the form commonly quoted from these papers, not checked against their
text here): the SPH estimate of -rho div v with the neighbours' *volumes* instead
of their masses. The seed's eq. 7, sum_j m_j (v_i - v_j) . grad W, weighs a light
particle's neighbours across an interface by their (heavier) mass and smears a
density jump; this form only sees the velocity field, so each fluid keeps its own
density up to the interface. For a single fluid with equal densities it is exactly
eq. 7 (checked in the tests). Fluid neighbours only, or with ``walls=True`` dummy
wall particles too (:class:`taisph.terms.AdamiWall`), with their own (prescribed)
velocity and the volume their mass and density give.
"""

import taichi as ti

from ..messages import InputError
from .base import VolumeTerm


@ti.data_oriented
class ContinuityColagrossi(VolumeTerm):
    name = "continuity_colagrossi"
    integrates = {"density": "d_density"}
    takes_walls = True

    def check(self, scene):
        if "continuity" in scene.terms_by_name:
            raise InputError("use either Continuity (seed eq. 7) or ContinuityColagrossi, not both")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if self.sees(s, j):
            vij = s.Sv[q.velocity, i] - s.Sv[q.velocity, j]
            rates.d[self.r.d_density] += s.Ss[q.density, i] * s.Ss[q.volume, j] * vij.dot(grad)
