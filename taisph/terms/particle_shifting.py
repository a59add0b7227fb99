"""Particle shifting: particles drift from crowded to sparse regions, keeping the
particle distribution regular (Sun, Colagrossi, Marrone & Zhang 2017, CMAME 315:25,
the delta-plus-SPH shifting; after Lind et al. 2012 and Xu et al. 2009).

    delta x_a = -CFL Ma (2h)^2 sum_b [1 + R (W_ab / W(dx))^n] grad_a W_ab m_b / rho_b

per step, with R = 0.2, n = 4, Ma = U/c0 and CFL = c0 dt / h, i.e. a shifting
velocity (``rates.shift``: it moves particles, it is not their momentum)

    delta u_a = -4 U h sum_b [1 + 0.2 (W_ab / W(dx))^4] grad_a W_ab m_b / rho_b.

``shift_speed`` is the reference speed U (m/s; the flow's largest speed), ``shift_dx``
the initial particle spacing (default: the scene's dx). The sum is the gradient of the
particle concentration (zero on a regular lattice); the W^4 part is a short-range
repulsion against particle pairing (tensile instability).

Why: a Lagrangian particle lattice is stretched by the flow. At a stagnation point of
strain rate S, particles are squeezed to e^{-St} and pulled to e^{St} of their spacing,
and once the spacing along the stretched direction approaches the kernel radius, SPH
sums stop approximating derivatives. In the Taylor-Green vortex this destroys the
solution at t ~ 2/(kU) (the "taylor_green" case without shifting: L1 velocity error
0.29 at t = 0.2, see docs/accuracy.md).

Limits of this implementation: the quantities of a shifted particle are not corrected
for the displacement (the "simple procedure" of Sun et al. 2017; the error is of the
order of the displacement times the field gradients), and there is no free-surface
treatment: near a free surface the concentration gradient points outwards and shifting
would push particles out of the fluid. Use it for confined or periodic flows.

Walls: the particles of walls (dummy or any other) count in the sum like fluid ones,
with their volume m_b / rho_b: they fill the space beyond the wall, so that next to a
wall the concentration is full and its gradient does not push the fluid into the wall.
(Without them, the gradient at a wall points out of the fluid, as at a free surface:
the cylinder case's fluid was pushed through the channel's walls and its run stopped
at 0.46 s.) Open boundaries' buffer particles are fluid particles and count too.
"""

import taichi as ti

from ..engine.layout import FLUID, WALL
from ..messages import InputError
from .base import Term


@ti.data_oriented
class ParticleShifting(Term):
    name = "particle_shifting"
    params = {"shift_speed": None, "shift_dx": None}
    wall_range = "support"  # walls fill the kernel sums (see the module docstring)
    has_shift = True

    def check(self, scene):
        if self.values.get("shift_dx") is None:
            self.values["shift_dx"] = scene.dx
        u = self.values.get("shift_speed")
        if u is None or not u >= 0:
            raise InputError(f"particle_shifting needs shift_speed >= 0 (the reference flow speed, m/s), got {u!r}")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] == FLUID or s.Si[q.kind, j] == WALL:
            h = s.params[self.p_h]
            ratio = self.w(s, r) / self.w(s, s.params[self.p.shift_dx])
            ratio2 = ratio * ratio
            weight = 1.0 + 0.2 * ratio2 * ratio2
            coeff = 4.0 * s.params[self.p.shift_speed] * h
            rates.shift -= coeff * weight * s.Ss[q.mass, j] / s.Ss[q.density, j] * grad
