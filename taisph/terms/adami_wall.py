"""Dummy wall particles with pressure extrapolated from the fluid (Adami, Hu & Adams
2012, J. Comput. Phys. 231:7057, eqs. 22-28).

Before every force pass, each wall particle w takes a pressure from the fluid
particles f around it,

    p_w = ( sum_f p_f W_wf + (g - a_w) . sum_f rho_f r_wf W_wf ) / sum_f W_wf,   r_wf = x_w - x_f,

(the second sum is the hydrostatic head between the fluid and the wall particle,
:func:`taisph.terms.hydrostatic.head`), and the density that gives that pressure by
the inverse equation of state, rho_w = rho0 (1 + p_w / B)^(1/gamma)
(:meth:`taisph.eos.Tait.density_at`). The fluid then sees wall particles in its
pressure gradient and continuity sums like any neighbour
(``PressureGradient(walls=True)``, ``Continuity(walls=True)``), so the wall pushes
back exactly as hard as the fluid presses on it: no gap, no repulsive-force layer,
and the hydrostatic pressure is right up to the wall.

For viscous (no-slip) walls each wall particle also gets the velocity
v_w = 2 v_wall - sum_f v_f W_wf / sum_f W_wf (Adami eq. 23), which
``LaminarViscosity(walls=True)`` uses; the continuity sum uses the wall's own
(prescribed) velocity. a_w is the wall's acceleration: zero for walls that move at
constant velocity, the body's for moving and floating bodies
(:mod:`taisph.terms.rigid_bodies`, the ``wall_acceleration`` row). ``g`` is the scene's
body force (the ``gravity`` parameter of :class:`Gravity`), zero without one. A wall
particle with no fluid neighbour gets p_w = 0.

``AdamiWall(per_phase=True)`` (two phases, :func:`taisph.scene.phases.two_phase_terms`):
each wall particle also takes one pressure from the fluid of the first material and one
from the others, p_w^k by the same sum over phase k's particles only (the mixed p_w where
a phase has none nearby), and a fluid particle reads the one of its own phase
(:class:`taisph.terms.PressureHuAdams`). A wall beside an interface then pushes each
phase as hard as that phase presses on it: a single p_w extrapolates the water's
hydrostatic gradient into the air beside it (10 Pa a millimetre above a still water
surface), a suction that pulls the air into the wall (docs/multiphase.md).

Walls need enough layers to fill the kernel support of the fluid next to them:
ceil(support radius / spacing) layers of particles ``dx`` apart (3 for the cubic
spline or Wendland with h = 1.3 dx, 4 for the Gaussian). The inverse EOS is floored
at (1 + p_w/B) >= 0.05 (a wall tension of -0.95 B) so that a wall never gets a
non-physical density.
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .hydrostatic import head as hydrostatic_head
from .base import NeighbourPass, Term


@ti.data_oriented
class AdamiWall(Term):
    name = "dummy_walls"
    vectors = ("wall_velocity",)
    derived = ("wall_velocity",)
    outputs = ()

    def __init__(self, per_phase: bool = False, **values):
        super().__init__(**values)
        self.options["per_phase"] = bool(per_phase)
        if per_phase:  # the wall's pressure as the first material sees it, and as the others do
            self.scalars = ("phase_pressure_first", "phase_pressure_rest")
            self.derived = ("wall_velocity", "phase_pressure_first", "phase_pressure_rest")

    @property
    def per_phase(self) -> bool:
        return self.options.get("per_phase", False)

    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        # the body force, if the scene has one (the Gravity term's parameter row)
        t.p_gravity = param_rows.get("gravity")
        t.has_gravity = t.p_gravity is not None
        t.a_row = getattr(layout.q, "wall_acceleration", -1)  # moving bodies (taisph.terms.rigid_bodies)
        return t

    def passes(self):
        return [_WallPressure(self)]

    def check(self, scene):
        if scene.n_wall == 0:
            raise InputError("dummy_walls: the scene has no wall particles")
        terms = scene.terms_by_name
        riemann = terms.get("riemann")  # the Riemann formulation: continuity and pressure in one term
        # how the fluid's density is had, and its pressure force: the seed's forms, the multiphase ones, Riemann's
        density = next((terms[n] for n in ("continuity", "continuity_colagrossi", "summation_density") if n in terms),
                       riemann)
        pressure = next((terms[n] for n in ("pressure", "pressure_hu_adams") if n in terms), riemann)
        for name, t in (("pressure", pressure), ("continuity", density)):
            if t is None or not t.options.get("walls"):
                raise InputError(
                    f"dummy_walls needs the {name!r} term with walls=True (e.g. PressureGradient(walls=True), "
                    "Continuity(walls=True) or SummationDensity(walls=True)): "
                    "otherwise the wall pressure acts on nothing"
                )


@ti.data_oriented
class _WallPressure(NeighbourPass):
    select = "wall"
    rederive = True  # pressure, sound speed and P/rho^2 of the wall from its new density

    def __init__(self, term):
        self.t = term
        self.q = term.q
        self.m = term.m
        self.dim = None

    @ti.func
    def init(self, s: ti.template(), i):
        # [sum W, sum p W, sum rho r W (dim), sum v W (dim)], then per phase (first material, the
        # others) [sum W, sum p W, sum rho r W (dim)]
        dim = ti.static(s.Sv[self.q.position, i].n)
        size = ti.static(2 + 2 * dim + (2 * (2 + dim) if self.t.per_phase else 0))
        return ti.Vector([0.0] * size)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] == FLUID:
            dim = ti.static(rij.n)
            acc[0] += w
            acc[1] += s.Ss[q.pressure, j] * w
            rho_w = s.Ss[q.density, j] * w
            v = s.Sv[q.velocity, j]
            for d in ti.static(range(dim)):
                acc[2 + d] += rho_w * rij[d]
                acc[2 + dim + d] += v[d] * w
            if ti.static(self.t.per_phase):
                base = 2 + 2 * dim
                if s.Si[q.material, j] != 0:
                    base += 2 + dim
                acc[base] += w
                acc[base + 1] += s.Ss[q.pressure, j] * w
                for d in ti.static(range(dim)):
                    acc[base + 2 + d] += rho_w * rij[d]

    @ti.func
    def extrapolated(self, s: ti.template(), i, acc, base, fallback):
        """(sum p W + (g - a_w) . sum rho r W) / sum W from the sums at acc[base:], or `fallback`
        where they are empty."""
        dim = ti.static(s.Sv[self.q.position, i].n)
        p = fallback
        if acc[base] > 0.0:
            head = 0.0
            if ti.static(self.t.has_gravity):  # g . sum_f rho_f r_wf W_wf
                head = hydrostatic_head(s, self.t.p_gravity,
                                        ti.Vector([acc[base + 2 + d] for d in ti.static(range(dim))]))
            if ti.static(self.t.a_row >= 0):  # (g - a_w): a wall that accelerates into the fluid presses
                a_w = s.Sv[self.t.a_row, i]
                for d in ti.static(range(dim)):
                    head -= a_w[d] * acc[base + 2 + d]
            p = (acc[base + 1] + head) / acc[base]
        return p

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        q = ti.static(self.q)
        dim = ti.static(s.Sv[q.position, i].n)
        v_wall = s.Sv[q.velocity, i]
        ghost = v_wall
        p = self.extrapolated(s, i, acc, 0, 0.0)
        if acc[0] > 0.0:
            for d in ti.static(range(dim)):
                ghost[d] = 2.0 * v_wall[d] - acc[2 + dim + d] / acc[0]
        if ti.static(self.t.per_phase):
            s.Ss[q.phase_pressure_first, i] = self.extrapolated(s, i, acc, 2 + 2 * dim, p)
            s.Ss[q.phase_pressure_rest, i] = self.extrapolated(s, i, acc, 4 + 3 * dim, p)
        s.Ss[q.density, i] = self.t.eos.density_at(s, s.Si[q.material, i], p)  # the inverse equation of state
        s.Sv[q.wall_velocity, i] = ghost
