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
solution at t ~ 2/(kU) (the "taylor_green" case without shifting, docs/accuracy.md).

Free surfaces (``free_surface=True``, compile-time; Sun et al. 2017 sec. 2.3, after Lind
et al. 2012): near a free surface the concentration gradient points out of the fluid, and
shifting alone pushes the surface out (tests/test_free_surface_shifting.py;
docs/validation.md, "delta+-SPH"). The same pair sum then gathers each particle's
moment matrix

    B_a = -sum_b V_b r_ab (x) grad_a W_ab        (= I inside the fluid, on a lattice)

and its smallest eigenvalue lambda_a tells where the particle is (on a square lattice with
the cubic spline, h = 1.3 dx: 0.5 in the surface row, 0.90 one row down, 1.01 below;
Wendland C2, h = 2 dx: 0.5, 0.70, 0.94, 1.00): lambda < 0.4 (a splash, a thin jet): no
shift; lambda < 0.75 (the surface layer): the shift's component along the normal
n = -G / |G|, G = sum_b V_b grad_a W_ab, is removed, delta u <- (I - n n) delta u; the
shift is kept otherwise: with the rule still water keeps its surface. Where the surface
meets a wall with friction (the dam break's back wall, with ``wall_friction``) it does not
hold: a film of water stays on the wall (also with no shift at all in the surface layer;
docs/validation.md, "delta+-SPH"), so the dam-break case refuses the two together. Scene
files switch shifting on with this rule (``physics.shifting = U``).

Cap (``shift_cap``, default 0.1): a particle moves by at most shift_cap * shift_dx per
step by shifting. The shift velocity above is a diffusion of the particle concentration
with coefficient ~4 U h, explicit in time: its step, 4 U h dt / h^2, is ~0.1 under the
weakly compressible time step (Sun et al.'s CFL Ma), but a solver with 10-50 times longer
steps overshoots with the same coefficient (the DFSPH solver does not take shifting).

Limits of this implementation: the quantities of a shifted particle are not corrected
for the displacement (the "simple procedure" of Sun et al. 2017; the error is of the
order of the displacement times the field gradients). Without ``free_surface`` it is for
confined or periodic flows. Nor are their volumes: a shift moves a particle without its
evolved density following, and still water's volume drifts without artificial viscosity,
in either formulation; viscosity slows it (docs/validation.md, "delta+-SPH"). Refused with
the Riemann formulation (``check``), which runs without artificial viscosity by default.

Walls: the particles of walls (dummy or any other) count in the sum like fluid ones,
with their volume m_b / rho_b: they fill the space beyond the wall, so that next to a
wall the concentration is full and its gradient does not push the fluid into the wall.
(Without them, the gradient at a wall points out of the fluid, as at a free surface,
and pushes the fluid through the wall.) Open boundaries' buffer particles are fluid
particles and count too.
"""

import math

import taichi as ti

from ..engine import status as st
from ..engine.layout import FLUID, WALL
from ..messages import InputError
from .base import Term


# Sun et al. 2017's bounds on lambda (the smallest eigenvalue of B, above)
SPLASH_LAMBDA = 0.4
SURFACE_LAMBDA = 0.75


@ti.data_oriented
class ParticleShifting(Term):
    """Parameters ``shift_speed`` (U, m/s), ``shift_dx`` (m), ``shift_cap`` (of shift_dx per
    step); option ``free_surface`` (above)."""

    name = "particle_shifting"
    params = {"shift_speed": None, "shift_dx": None, "shift_cap": 0.1}
    wall_range = "support"  # walls fill the kernel sums (see the module docstring)
    has_shift = True

    def __init__(self, free_surface: bool = False, **values):
        super().__init__(**values)
        self.accumulators = {}
        if free_surface:
            self.options["free_surface"] = True
            self.accumulators = {"shift_gradient": "vector", "shift_moment": "matrix"}

    def check(self, scene):
        if self.values.get("shift_dx") is None:
            self.values["shift_dx"] = scene.dx
        u = self.values.get("shift_speed")
        if u is None or not u >= 0:
            raise InputError(f"particle_shifting needs shift_speed >= 0 (the reference flow speed, m/s), got {u!r}")
        if any(t.name == "riemann" for t in scene.terms):
            # shifting changes the particles' volumes and the evolved density does not follow, so
            # still water's volume drifts, in either form; artificial viscosity slows it, and the
            # Riemann form runs without it by default (docs/validation.md, "delta+-SPH")
            raise InputError("particle_shifting cannot be used with the Riemann formulation: still water under "
                             "both drifted (pressure error 35 % of rho g H in 3 s); use the symmetric form "
                             "(formulation = \"symmetric\", Continuity + PressureGradient) with artificial "
                             "viscosity, where shifting with density diffusion is delta-plus-SPH")
        cap = self.values.get("shift_cap")
        if cap is None or not 0 < cap <= 1:
            raise InputError(f"particle_shifting needs 0 < shift_cap <= 1 (the largest shift per step, in shift_dx), "
                             f"got {cap!r}")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] == FLUID or s.Si[q.kind, j] == WALL:
            h = s.params[self.p_h]
            ratio = self.w(s, r) / self.w(s, s.params[self.p.shift_dx])
            ratio2 = ratio * ratio
            weight = 1.0 + 0.2 * ratio2 * ratio2
            coeff = 4.0 * s.params[self.p.shift_speed] * h
            volume = s.Ss[q.mass, j] / s.Ss[q.density, j]
            rates.shift -= coeff * weight * volume * grad
            if ti.static(self.options.get("free_surface", False)):
                rates.shift_gradient += volume * grad
                rates.shift_moment -= volume * rij.outer_product(grad)

    @ti.func
    def finish(self, s: ti.template(), i, rates: ti.template()):
        if ti.static(self.options.get("free_surface", False)):
            lam = _smallest_eigenvalue(rates.shift_moment)
            if lam < SPLASH_LAMBDA:
                rates.shift *= 0.0
            elif lam < SURFACE_LAMBDA:
                g = rates.shift_gradient
                g2 = g.norm_sqr()
                if g2 > 0.0:
                    normal = g / ti.sqrt(g2)
                    rates.shift -= rates.shift.dot(normal) * normal  # (I - n n) delta u, as Sun et al.
        # at most shift_cap * shift_dx per step (the module docstring: "Cap")
        step = rates.shift.norm() * s.status[st.DT]
        most = s.params[self.p.shift_cap] * s.params[self.p.shift_dx]
        if step > most:
            rates.shift *= most / step


@ti.func
def _smallest_eigenvalue(b):
    """The smallest eigenvalue of the symmetric part of the 1x1, 2x2 or 3x3 matrix b (3x3:
    the trigonometric solution of the characteristic cubic, Smith 1961, CACM 4:168)."""
    lam = b[0, 0]
    if ti.static(b.n == 2):
        off = 0.5 * (b[0, 1] + b[1, 0])
        half = 0.5 * (b[0, 0] - b[1, 1])
        lam = 0.5 * (b[0, 0] + b[1, 1]) - ti.sqrt(half * half + off * off)
    elif ti.static(b.n == 3):
        a = 0.5 * (b + b.transpose())
        p1 = a[0, 1] ** 2 + a[0, 2] ** 2 + a[1, 2] ** 2
        mean = (a[0, 0] + a[1, 1] + a[2, 2]) / 3.0
        p2 = (a[0, 0] - mean) ** 2 + (a[1, 1] - mean) ** 2 + (a[2, 2] - mean) ** 2 + 2.0 * p1
        lam = mean
        if p2 > 1e-24:
            p = ti.sqrt(p2 / 6.0)
            c = a / p
            for d in ti.static(range(3)):
                c[d, d] -= mean / p
            half_det = 0.5 * c.determinant()
            phi = ti.acos(ti.min(1.0, ti.max(-1.0, half_det))) / 3.0
            lam = mean + 2.0 * p * ti.cos(phi + 2.0 * math.pi / 3.0)
    return lam
