"""Artificial thermal conductivity (Price 2008, J. Comput. Phys. 227:10040).

    de_a/dt += sum_b alpha_u m_b v_sig (e_a - e_b) / rho_ab  (r_hat_ab . grad_a W_ab),
    v_sig = sqrt(|P_a - P_b| / rho_ab),   rho_ab = (rho_a + rho_b) / 2.

A diffusion of internal energy e across a discontinuity in e, which the inviscid SPH
equations leave sharp at a contact discontinuity while the density there is smoothed
by the kernel: the mismatch gives the well-known pressure "blip" at the contact of a
shock tube. r_hat . grad W < 0 for every kernel here, so energy flows from hot to
cold; the sum is antisymmetric in a, b, so total energy is conserved. The signal
speed follows Price (2008): it vanishes where pressure is uniform, so the term acts at
contacts and shocks only. Some codes write the term with a factor 1/2, which is the
same as halving alpha_u. Needs the energy equation (:class:`InternalEnergy`).
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .base import Term


@ti.data_oriented
class ArtificialConductivity(Term):
    """Parameter: ``alpha_u`` (dimensionless, ~1)."""

    name = "artificial_conductivity"
    params = {"alpha_u": 1.0}
    wall_range = None  # fluid neighbours only

    def check(self, scene):
        if not any(t.integrates.get("energy") for t in scene.terms):
            raise InputError("artificial_conductivity needs the internal energy equation (InternalEnergy)")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] == FLUID:
            rho_ab = 0.5 * (s.Ss[q.density, i] + s.Ss[q.density, j])
            v_sig = ti.sqrt(ti.abs(s.Ss[q.pressure, i] - s.Ss[q.pressure, j]) / rho_ab)
            # r_hat . grad W = -|grad W| (no division by r: coincident particles are safe)
            rates.d[self.r.d_energy] -= (s.params[self.p.alpha_u] * s.Ss[q.mass, j] * v_sig
                                         * (s.Ss[q.energy, i] - s.Ss[q.energy, j]) / rho_ab) * grad.norm()
