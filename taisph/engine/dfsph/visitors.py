"""DFSPH's neighbour visitors: what one neighbour j contributes to particle i's sums
(:mod:`.solver` has the method and its equations, :mod:`.kernels` the kernels that
walk the neighbours and call these)."""

import taichi as ti

from .. import kernels
from ..layout import FLUID, WALL

# phi, the wall's mirror share: a wall particle b stands for the mirror image of the fluid
# particle i beside it, with i's pressure (p_b = p_i: phi k_i in the symmetric form) and
# the mirrored velocity (v_b = 2 v_wall - v_i: phi (v_i - v_wall) in the density rate).
# Counting the share in both keeps the pressure solve's matrix symmetric positive
# semi-definite; with phi in the pressure only it has negative eigenvalues at the walls,
# whose modes the Jacobi iteration amplifies. 2 is p_b = p_i in the symmetric form (the other
# values tried: docs/dfsph.md, "Walls").
WALL_MIRROR = 2.0

# epsilon of the pairing repulsion (NonPressure): two fluid particles closer than the
# lattice spacing dx push each other apart with epsilon ((W(r) / W(dx))^4 - 1) times their
# pressure force, as in Monaghan's (2000) artificial pressure, but only below dx, so that
# it is zero on the lattice and in any arrangement without close pairs. Without it, water
# at rest with the cubic spline (h = 1.3 dx) pairs, the pairing instability of B-splines
# (docs/dfsph.md, "Still water", with the values of epsilon tried).
PAIRING_REPULSION = 0.05


@ti.data_oriented
class DensityVisitor:
    """Step 1's neighbour visitor: density, the factor's sums, D rho/Dt, the pair list."""

    def __init__(self, solver, plist):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.plist = plist
        self.wall_velocity = "wall_velocity" in solver.layout.vectors
        self.p_inv_h = solver.param_rows["inv_h"]
        self.p_w_norm = solver.param_rows["w_norm"]
        self.p_grad_norm = solver.param_rows["grad_norm"]

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        q = ti.static(self.q)
        kind = s.Si[q.kind, j]
        if kind == FLUID or kind == WALL:
            x = ti.sqrt(r2) * s.params[self.p_inv_h]
            mj = s.Ss[q.mass, j]
            coef = mj * s.params[self.p_grad_norm] * self.kern.g(x)
            acc.rho += mj * s.params[self.p_w_norm] * self.kern.f(x)
            if kind == WALL:
                coef *= WALL_MIRROR  # the mirror share (above): the pair list stores it
            g = coef * rij
            vi = s.Sv[q.velocity, i]
            acc.div += (vi - s.Sv[q.velocity, j]).dot(g)
            if kind == FLUID:
                acc.gf += g
                acc.g2 += g.dot(g)
            else:
                acc.gb += g
            self.plist.store(s, i, acc.k, j, coef)
            acc.k += 1


@ti.data_oriented
class WallGather:
    """Step 1's visitor of a wall particle: the sums of its no-slip velocity over its
    fluid neighbours, sum_f W_wf v_f and sum_f W_wf (gathered per wall particle rather
    than scattered by the fluid with atomic adds, whose order, and so round-off, varied
    from run to run with several threads)."""

    def __init__(self, solver):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.p_inv_h = solver.param_rows["inv_h"]

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        if s.Si[self.q.kind, j] == FLUID:
            w = self.kern.f(ti.sqrt(r2) * s.params[self.p_inv_h])
            acc.w += w
            acc.v += w * s.Sv[self.q.velocity, j]


@ti.data_oriented
class NonPressure:
    """Step 3's visitor of the pair list: the scene's pair terms (as the weakly
    compressible force pass sums them), the walls' hydrostatic head (with gravity:
    it makes a hydrostatic field an equilibrium at a flat wall; docs/dfsph.md, "Walls")
    and the pairing repulsion of fluid pairs closer than dx (:data:`PAIRING_REPULSION`,
    with the last step's pressures)."""

    def __init__(self, solver):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.terms = [t for t in solver.terms if t.has_pair]
        rows = solver.param_rows
        self.p_gravity = rows.get("gravity")
        self.head = self.p_gravity is not None
        self.p_inv_h, self.p_scale = rows["inv_h"], rows["dfsph_gradient_scale"]
        self.p_pair_q, self.p_pair_w = rows["dfsph_pair_q"], rows["dfsph_pair_w"]

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, coef, rates: ti.template()):
        """Pair (i, j) of the list, with coef = m_j F(r_ij) (grad_i W_ij = F r_ij; times the
        mirror share for a wall): the gradient needs no kernel evaluation (docs/dfsph.md, "Pair list")."""
        r = ti.sqrt(r2)
        wall = s.Si[self.q.kind, j] == WALL
        if wall:
            coef /= WALL_MIRROR  # the list stores a wall's coefficient with its mirror share
        grad = (coef / s.Ss[self.q.mass, j]) * rij
        for t in ti.static(self.terms):
            ti.static(kernels._traced(t.name, "pair"))
            t.pair(s, i, j, rij, r, grad, rates)
        if ti.static(self.head):
            if wall:
                # p_wall - p_i = rho_i g . (x_wall - x_i): a_i -= m_b (that / rho_i^2) grad W
                # (a pressure force: scaled like the solve's, kernels.py)
                g = ti.Vector([s.params[self.p_gravity + d] for d in ti.static(range(rij.n))])
                head = s.params[self.p_scale] * g.dot(rij) / s.Ss[self.q.density, i]
                rates.acc += (coef * head) * rij
        if s.Si[self.q.kind, j] == FLUID:
            q2 = r2 * s.params[self.p_inv_h] * s.params[self.p_inv_h]
            pair_q = s.params[self.p_pair_q]
            if q2 < pair_q * pair_q:  # closer than dx: the pairing repulsion (PAIRING_REPULSION)
                ratio = self.kern.f(ti.sqrt(q2)) / s.params[self.p_pair_w]
                ratio *= ratio
                push = PAIRING_REPULSION * (ratio * ratio - 1.0) * s.params[self.p_scale]
                rates.acc -= (push * coef * (s.Ss[self.q.kappa, i] + s.Ss[self.q.kappa, j])) * rij
