"""Continuity and momentum with a low-dissipation Riemann solver between each pair
(Zhang, Hu & Adams 2017, "A weakly compressible SPH method based on a low-dissipation
Riemann solver", J. Comput. Phys. 335:605-620, eqs. 8-11).

Each pair (i, j) is a one-dimensional Riemann problem along e_ij = (x_j - x_i)/r_ij
between the left state i and the right state j: U_L = v_i . e_ij, U_R = v_j . e_ij,
p_L = p_i, p_R = p_j. Its linearised solution (pair means rho_m, c_m; c the sound speed)

    U* = (U_L + U_R)/2 + (p_L - p_R) / (2 rho_m c_m),
    p* = (p_L + p_R)/2 + beta rho_m (U_L - U_R) / 2,    beta = min(eta max(U_L - U_R, 0), c_m),

replaces the pair's velocity and pressure in the equations:

    d rho_i/dt = 2 rho_i sum_j (m_j/rho_j) (v_i - v*_ij) . grad_i W_ij,
                 v*_ij = U* e_ij + ((v_i + v_j)/2 - (U_L + U_R)/2 e_ij)
               = rho_i sum_j (m_j/rho_j) [v_ij . grad_i W_ij + (p_i - p_j - p^H_ij) F_ij r_ij / (rho_m c_m)],
    dv_i/dt    = -2 sum_j m_j p*_ij / (rho_i rho_j) grad_i W_ij,

with grad_i W_ij = F_ij (x_i - x_j). The continuity equation keeps the Riemann
solver's full dissipation (a pressure, and so density, diffusion like delta-SPH's); the
momentum equation's is limited by beta (eta = 3 in the paper, the ``riemann_eta``
parameter): it acts only between particles that approach each other and vanishes with
their approach speed, so a smooth flow keeps little numerical viscosity (the reason for
its smooth, low-dissipation wall pressure; the paper's dam break against Buchner's P1).
Neither artificial viscosity nor density diffusion is needed (a scene may still add them).

Two choices of ours (what each gave against the alternative: docs/validation.md, "The
Riemann formulation"):
- The hydrostatic part of the pressure difference, p^H_ij = rho_m g . (x_i - x_j), is
  taken out of the continuity equation's diffusion when the scene has gravity, as the
  density diffusion term does (Fourtakas et al. 2019): without it the diffusion carries
  mass up a column at rest until its hydrostatic density is flat.
- A dummy-wall particle (``walls=True``, :class:`taisph.terms.AdamiWall`) is the right
  state with its extrapolated pressure and density; its velocity is the mirror of i's
  along the walls' normal n_i at i (U_L - U_R = 2 (v_i - v_wall) . n_i, the paper's
  U_R = 2 u_wall - U_L), n_i from a neighbour sum over the walls before the force pass
  (:class:`_WallNormal`). Along r_ij instead, the dissipation acts as a friction on the
  fluid sliding past and holds the dam break's front back. The continuity
  equation's diffusion skips walls (their pressure is the fluid's, extrapolated).

Every pair contributes equal and opposite momentum (p* and rho_i rho_j are symmetric,
grad_i W_ij antisymmetric): linear momentum is conserved exactly.
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .hydrostatic import head as hydrostatic_head
from .base import NeighbourPass, Term


@ti.data_oriented
class Riemann(Term):
    """Parameters: ``riemann_eta`` (the dissipation limiter's eta, 3)."""

    name = "riemann"
    params = {"riemann_eta": 3.0}
    integrates = {"density": "d_density"}

    takes_walls = True

    def __init__(self, walls: bool = False, **values):
        super().__init__(walls=walls, **values)
        if walls:  # the walls' normal at each fluid particle (_WallNormal)
            self.vectors = ("wall_normal",)
            self.derived = ("wall_normal",)

    def passes(self):
        return [_WallNormal(self)] if self.with_walls else []

    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        t.p_gravity = param_rows.get("gravity")
        t.has_gravity = t.p_gravity is not None
        return t

    def check(self, scene):
        for name in ("continuity", "pressure", "continuity_colagrossi", "pressure_hu_adams"):
            if name in scene.terms_by_name:
                raise InputError(f"riemann replaces the continuity and pressure terms: the scene also has {name}; "
                                 "use one formulation")
        if not self.values["riemann_eta"] >= 0:
            raise InputError(f"riemann: riemann_eta must be >= 0, got {self.values['riemann_eta']!r}")

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if self.sees(s, j) and r > 0.0:
            rho_i = s.Ss[q.density, i]
            rho_j = s.Ss[q.density, j]
            p_i = s.Ss[q.pressure, i]
            p_j = s.Ss[q.pressure, j]
            rho_m = 0.5 * (rho_i + rho_j)
            c_m = 0.5 * (self.eos.sound_speed(s, i) + self.eos.sound_speed(s, j))
            vij = s.Sv[q.velocity, i] - s.Sv[q.velocity, j]
            approach = -vij.dot(rij) / r  # U_L - U_R, > 0 when i and j approach
            diffuse = 1.0
            if ti.static(self.with_walls):
                if s.Si[q.kind, j] != FLUID:
                    # a wall: the mirrored state, U_R = 2 u_wall - U_L, along the wall's normal at i
                    # (not along r_ij, which would make the dissipation a friction on fluid sliding
                    # past); no diffusion (the wall's pressure is extrapolated from the fluid's)
                    normal = s.Sv[q.wall_normal, i]
                    length = normal.norm()
                    approach = 0.0
                    if length > 0.0:
                        approach = 2.0 * vij.dot(normal) / length
                    diffuse = 0.0
            beta = ti.min(s.params[self.p.riemann_eta] * ti.max(approach, 0.0), c_m)
            p_star = 0.5 * (p_i + p_j) + 0.5 * beta * rho_m * approach
            mj = s.Ss[q.mass, j]
            rates.acc -= (2.0 * mj * p_star / (rho_i * rho_j)) * grad
            dp = p_i - p_j
            if ti.static(self.has_gravity):
                dp -= rho_m * hydrostatic_head(s, self.p_gravity, rij)  # hydrostatic p_i - p_j = rho g . r_ij
            f_r = grad.dot(rij) / r  # F_ij r_ij (< 0)
            rates.d[self.r.d_density] += rho_i * (mj / rho_j) * (vij.dot(grad) + diffuse * dp * f_r / (rho_m * c_m))


@ti.data_oriented
class _WallNormal(NeighbourPass):
    """n_i = sum_walls (m_w / rho0_w) grad_i W_iw: towards the walls near fluid particle i
    (zero away from them; along the bisector in a corner), the direction of the mirrored
    Riemann state at walls."""

    select = "fluid"

    def __init__(self, term):
        self.q = term.q
        self.m = term.m

    @ti.func
    def init(self, s: ti.template(), i):
        dim = ti.static(s.Sv[self.q.position, i].n)
        return ti.Vector([0.0] * dim)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] != FLUID:
            acc += (s.Ss[q.mass, j] / s.mat[s.Si[q.material, j], self.m.rho0]) * grad

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        s.Sv[self.q.wall_normal, i] = acc
