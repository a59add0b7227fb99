"""DFSPH's neighbour visitors: what one neighbour j contributes to particle i's sums
(:mod:`.solver` has the method and its equations, :mod:`.kernels` the kernels that
walk the neighbours and call these)."""

import taichi as ti

from .. import kernels
from ..layout import FLUID, WALL


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
            g = coef * rij
            acc.rho += mj * s.params[self.p_w_norm] * self.kern.f(x)
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
    compressible force pass sums them) and the walls' hydrostatic head (with gravity:
    it makes a hydrostatic field an equilibrium at a flat wall; docs/dfsph.md, "Walls")."""

    def __init__(self, solver):
        self.q = solver.layout.q
        self.terms = [t for t in solver.terms if t.has_pair]
        self.p_gravity = solver.param_rows.get("gravity")
        self.head = self.p_gravity is not None

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, coef, rates: ti.template()):
        """Pair (i, j) of the list, with coef = m_j F(r_ij) (grad_i W_ij = F r_ij): the
        gradient needs no kernel evaluation (docs/dfsph.md, "Pair list")."""
        r = ti.sqrt(r2)
        grad = (coef / s.Ss[self.q.mass, j]) * rij
        for t in ti.static(self.terms):
            ti.static(kernels._traced(t.name, "pair"))
            t.pair(s, i, j, rij, r, grad, rates)
        if ti.static(self.head):
            if s.Si[self.q.kind, j] == WALL:
                # p_wall - p_i = rho_i g . (x_wall - x_i): a_i -= m_b (that / rho_i^2) grad W
                g = ti.Vector([s.params[self.p_gravity + d] for d in ti.static(range(rij.n))])
                rates.acc += (coef * g.dot(rij) / s.Ss[self.q.density, i]) * rij
