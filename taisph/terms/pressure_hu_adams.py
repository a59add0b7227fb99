"""Momentum equation, pressure part, multiphase form of Hu & Adams (2006).

    dv_i/dt = - (1/m_i) sum_j (V_i^2 + V_j^2) p~_ij grad_i W_ij,

    V = m / rho (particle volume),   p~_ij = (rho_j p_i + rho_i p_j) / (rho_i + rho_j),

X. Y. Hu and N. A. Adams, "A multi-phase SPH method for macroscopic and mesoscopic
flows", J. Comput. Phys. 213:844-861 (2006): their inviscid momentum equation with
the density-weighted inter-particle pressure (the paper's own viscous term is not
used; taisph adds Monaghan's artificial viscosity as a separate term). The paper's
text was not available to us: the form is the one commonly quoted from it, and its
properties below are checked by the tests, not by comparison with the paper.
The same form is the momentum equation of Adami, Hu & Adams (2010), J. Comput. Phys.
229:5011, eq. 6, whose multiphase runs reach density ratio 1000 with a background
pressure (``Material.background_pressure``, docs/multiphase.md).

Every pair contributes equal and opposite forces m_i dv_i = -m_j dv_j along r_ij
(V_i^2 + V_j^2 and p~_ij are symmetric, grad_i W_ij is antisymmetric), so linear
and angular momentum are conserved exactly, as with the seed's eq. 8. The particle
volume V_i = m_i / rho_i uses each particle's *own* density, and p~_ij weights the
pressures by the *other* particle's density: across an interface between fluids
of different density (a density jump of 2 in ``two_fluids``) the pressure force
stays continuous and the interface stays sharp. For a single fluid with equal
masses and densities the term is exactly the seed's eq. 8 (checked in the tests).

Fluid neighbours only (walls act by the Lennard-Jones force), or with ``walls=True``
dummy wall particles too (Adami, Hu & Adams 2012, :class:`taisph.terms.AdamiWall`).
A wall particle carries one pressure p_w (or, with ``AdamiWall(per_phase=True)``, one
per phase, and i reads its own phase's), and for fluid particle i it takes the density
of i's own phase at that pressure, rho_w = the inverse
equation of state of i's material at p_w (Adami et al. 2012 eq. 28, per phase), in the
weight p~_iw; its volume is its own, m_w / rho_w of its stored density. A light phase
beside a wall is then pushed back by the wall as hard as it presses on it, whatever
the wall's own material.
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .base import VolumeTerm


@ti.data_oriented
class PressureHuAdams(VolumeTerm):
    name = "pressure_hu_adams"
    takes_walls = True

    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        # the walls' pressure per phase, where the wall term keeps one (AdamiWall(per_phase=True))
        t.phase_rows = (getattr(layout.q, "phase_pressure_first", -1), getattr(layout.q, "phase_pressure_rest", -1))
        return t

    def check(self, scene):
        if "pressure" in scene.terms_by_name:
            raise InputError("use either PressureGradient (seed eq. 8) or PressureHuAdams, not both")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if self.sees(s, j):
            rho_i = s.Ss[q.density, i]
            rho_j = s.Ss[q.density, j]
            v_i = s.Ss[q.volume, i]
            v_j = s.Ss[q.volume, j]
            p_j = s.Ss[q.pressure, j]
            if ti.static(self.with_walls):
                if s.Si[q.kind, j] != FLUID:  # the wall, as seen by i's phase
                    if ti.static(self.phase_rows[0] >= 0):
                        p_j = s.Ss[self.phase_rows[0], j] if s.Si[q.material, i] == 0 else s.Ss[self.phase_rows[1], j]
                    rho_j = self.eos.density_at(s, s.Si[q.material, i], p_j)
            p_ij = (rho_j * s.Ss[q.pressure, i] + rho_i * p_j) / (rho_i + rho_j)
            rates.acc -= ((v_i * v_i + v_j * v_j) * p_ij / s.Ss[q.mass, i]) * grad
