"""The kernel bodies of a DFSPH step (:mod:`.solver` has the method, its equations and
the host side that iterates the solves): :class:`StepKernels`, the kernels of one field set.
What one neighbour contributes to each sum is in :mod:`.visitors`.

The choices of the method are compiled in (docs/dfsph.md, "The measured choices",
records the alternatives and what each gave): each solve starts from the last step's
pressures in full (warm start 1: a partial warm start leaves still water unconverged);
the update is a projected Jacobi iteration, in which pressures may fall but not below
zero (SPlisHSPlasH's pressures that only rise leave still water's pressure far off); a
particle short of the rest density (a free surface) must keep its density; the walls
mirror the pressure with the share :data:`WALL_MIRROR` and add the hydrostatic head
(:class:`.visitors.NonPressure`).
"""

import taichi as ti

from .. import guards, kernels
from . import pairs
from .. import status as st
from ..layout import FLUID, WALL
from .visitors import WALL_MIRROR, DensityVisitor, NonPressure, WallGather  # noqa: F401 (WALL_MIRROR: the probes')

CHUNKS = 128  # the error sums: per chunk of particles, then a serial sum (an atomic add costs 5x more)


@ti.func
def _chunk(n, c):
    """Particles [begin, end) of chunk c of n particles in CHUNKS chunks."""
    size = (n + CHUNKS - 1) // CHUNKS
    return c * size, ti.min(c * size + size, n)


@ti.func
def _mean_over_chunks(x: ti.template(), slot: ti.template()):
    """(Serial.) x.result[slot] = the chunks' error sums over their fluid particle count."""
    total = ti.cast(0.0, ti.f64)
    fluid = ti.cast(0.0, ti.f64)
    for c in range(CHUNKS):
        total += x.part[c, 0]
        fluid += x.part[c, 1]
    x.result[slot] = total / ti.max(fluid, 1.0)


class StepKernels:
    """The kernel bodies of a DFSPH step on one field set (its pair list bound)."""

    def __init__(self, solver, extra):
        self.solver = solver
        self.x = extra
        self.q = q = solver.layout.q
        self.dim, self.real = solver.dim, solver.real
        self.grid = solver.grid
        self.plist = pairs.PairList(extra.pairs, solver.grid, q.position)
        self.local = kernels._local_parameters(solver)
        self.p = solver.param_rows
        self.has_shift = solver.has_shift
        self.wall_velocity = "wall_velocity" in solver.layout.vectors
        self.gravity_row = solver.param_rows.get("gravity")

    # --- step 1 --------------------------------------------------------------------
    def density(self):
        q, grid, plist, x = self.q, self.grid, self.plist, self.x
        dim, real = self.dim, self.real
        vec = ti.types.vector(dim, real)
        Acc = ti.types.struct(rho=real, div=real, g2=real, gf=vec, gb=vec, k=ti.i32)
        WallSums = ti.types.struct(w=real, v=vec)
        visitor = DensityVisitor(self.solver, plist)
        gather = WallGather(self.solver)
        kern = self.solver.kernel
        p = self.p
        local = self.local

        wall_velocity = self.wall_velocity
        rho0_col = self.solver.eos.m.rho0

        @ti.func
        def body(s_mem: ti.template(), t_target):
            ti.static(kernels._traced("dfsph", "density"))
            for i in range(s_mem.sizes[st.N_PARTICLES]):
                kind = s_mem.Si[q.kind, i]
                if kind == FLUID:
                    s = ti.static(s_mem._replace(params=local(s_mem)))
                    mi = s.Ss[q.mass, i]
                    acc = Acc(rho=mi * s.params[p["w_norm"]] * kern.f(0.0), div=0.0, g2=0.0,
                              gf=ti.Vector.zero(real, dim), gb=ti.Vector.zero(real, dim), k=0)
                    grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p["support2"]], visitor, acc)
                    if not plist.close(s, i, acc.k):
                        guards.trip(s, q, i, st.CROWDED)
                    s.Ss[q.density, i] = acc.rho
                    gsum = acc.gf + acc.gb  # acc.gb has the walls' mirror share
                    denominator = gsum.dot(gsum) + acc.g2
                    # the diagonal of the solve's matrix, whose pressure force is scaled (gradient_scale)
                    denominator *= s.params[p["dfsph_gradient_scale"]]
                    s.Ss[q.alpha, i] = 1.0 / denominator if denominator > 0.0 else 0.0
                    s.Sv[q.gsum, i] = gsum
                    s.Ss[q.source, i] = acc.div  # kappa_v: the last step's, the solve's warm start
                    if acc.k < s.params[p["dfsph_min_neighbours"]]:
                        # a splash: no warm start. Its factor is huge when a neighbour stands near the
                        # support's edge, and so its last pressure; kept, it kicks the particle at the
                        # next encounter unless iterated away, which a mean error does not ask for
                        s.Ss[q.kappa, i] = 0.0
                        s.Ss[q.kappa_v, i] = 0.0
                else:  # walls (and removed particles): no pressure, no acceleration, their own velocity
                    s_mem.Ss[q.kappa, i] = 0.0
                    s_mem.Ss[q.kappa_v, i] = 0.0
                    s_mem.Sv[q.v_pred, i] = s_mem.Sv[q.velocity, i]  # a wall moves as it is told
                    s_mem.Sv[q.vstar, i] = s_mem.Sv[q.velocity, i]
                    x.pairs.count[i] = 0
                    if ti.static(wall_velocity):  # the wall's no-slip sums, for step 3
                        s = ti.static(s_mem._replace(params=local(s_mem)))
                        sums = WallSums(w=0.0, v=ti.Vector.zero(real, dim))
                        if kind == WALL:
                            grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p["support2"]], gather, sums)
                        s.Ss[q.wall_weight, i] = sums.w
                        s.Sv[q.wall_velocity, i] = sums.v
            # the divergence error before any iteration (result[1]): within the tolerance, the
            # divergence solve has nothing to do (the host skips it, and ``middle`` with it)
            for c in range(CHUNKS):
                dt = ti.cast(s_mem.status[st.DT], real)
                begin, end = _chunk(s_mem.sizes[st.N_PARTICLES], c)
                error = ti.cast(0.0, ti.f64)
                count = 0
                for i in range(begin, end):
                    if s_mem.Si[q.kind, i] == FLUID:
                        if x.pairs.count[i] >= s_mem.params[p["dfsph_min_neighbours"]]:
                            rho0 = s_mem.mat[s_mem.Si[q.material, i], rho0_col]
                            error += ti.cast(ti.max(s_mem.Ss[q.source, i], 0.0) * dt / rho0, ti.f64)
                        count += 1
                x.part[c, 0] = error
                x.part[c, 1] = ti.cast(count, ti.f64)
            ti.loop_config(serialize=True)
            for _ in range(1):
                _mean_over_chunks(x, 1)

        return body

    # --- the pressure acceleration and one Jacobi iteration ----------------------------
    def _acceleration(self):
        """ti.func(s, i, row) -> a_i(k) of the pressures in scalar row `row`."""
        q, grid = self.q, self.grid
        f = self.x.pairs
        scale_row = self.p["dfsph_gradient_scale"]

        @ti.func
        def acceleration(s: ti.template(), i, row: ti.template()):
            xi = s.Sv[q.position, i]
            a = -s.Ss[row, i] * s.Sv[q.gsum, i]
            for k in range(f.count[i]):
                j = f.nbr[i, k]
                a -= (f.coef[i, k] * s.Ss[row, j]) * grid.separation(s, xi, s.Sv[q.position, j])
            scale = s.params[scale_row]
            return scale * a

        return acceleration

    def iteration(self, density: bool, first: bool = False):
        """One Jacobi iteration of the divergence (density False) or constant-density
        solve: the velocity every fluid particle would have with the current pressures,
        u = v + dt a(k) (v* + dt a(k) for the density), then the residuals, the updates
        and the mean error into ``result[0]`` (:meth:`_update`). The step applies the
        pressures of the last update, one better than those whose error was summed
        (applying those would save a pass over the pairs and cost more iterations than it
        saves: docs/dfsph.md, "Where the time goes")."""
        q, x, real = self.q, self.x, self.real
        local = self.local
        acceleration = self._acceleration()
        update = self._update(density)
        row = q.kappa if density else q.kappa_v
        base = q.vstar if density else q.velocity
        forces = self._non_pressure() if first else None

        @ti.func
        def body(s_mem: ti.template(), t_target):
            ti.static(kernels._traced("dfsph", "density solve" if density else "divergence solve"))
            dt0 = ti.cast(s_mem.status[st.DT], real)
            for i in range(s_mem.sizes[st.N_PARTICLES]):
                if s_mem.Si[q.kind, i] == FLUID:
                    if ti.static(first):  # v*, the source and v + dt a(k) in one walk of i's pairs
                        s_mem.Sv[q.v_pred, i] = forces(s_mem, i, dt0)
                    else:
                        s_mem.Sv[q.v_pred, i] = s_mem.Sv[base, i] + dt0 * acceleration(s_mem, i, row)
            for c in range(CHUNKS):
                s = ti.static(s_mem._replace(params=local(s_mem)))
                dt = ti.cast(s.status[st.DT], real)
                scale = dt * dt if ti.static(density) else dt
                begin, end = _chunk(s.sizes[st.N_PARTICLES], c)
                error = ti.cast(0.0, ti.f64)
                count = 0
                weight = ti.cast(x.result[2], real)  # the Chebyshev weight of this iteration (1: plain Jacobi)
                for i in range(begin, end):
                    if s.Si[q.kind, i] == FLUID:
                        error += ti.cast(update(s, i, dt, scale, weight), ti.f64)
                        count += 1
                x.part[c, 0] = error
                x.part[c, 1] = ti.cast(count, ti.f64)
            ti.loop_config(serialize=True)
            for _ in range(1):
                _mean_over_chunks(x, 0)

        return body

    def _update(self, density: bool):
        """ti.func(s, i, dt, scale, weight) -> fluid particle i's error: its residual, the
        density rate of u, sum_j coef (u_i - u_j) . r_ij (divergence), or the density error
        it leaves, max(rho - rest, 0) + dt times that (density): the source and the
        pressures' response in one sum over the pairs (docs/dfsph.md, "Where the time
        goes"); then its pressure's projected Jacobi update (scale: dt^2 or dt; weight:
        the Chebyshev weight of the density solve, :mod:`.chebyshev`)."""
        q, grid, real = self.q, self.grid, self.real
        f = self.x.pairs
        p = self.p
        row = q.kappa if density else q.kappa_v
        rho0_col = self.solver.eos.m.rho0

        @ti.func
        def update(s: ti.template(), i, dt, scale, weight):
            xi = s.Sv[q.position, i]
            ui = s.Sv[q.v_pred, i]
            rate = ti.cast(0.0, real)
            for k in range(f.count[i]):
                j = f.nbr[i, k]
                rate += f.coef[i, k] * (ui - s.Sv[q.v_pred, j]).dot(
                    grid.separation(s, xi, s.Sv[q.position, j]))
            residual = rate
            if ti.static(density):
                residual = s.Ss[q.source, i] + dt * rate  # source: the density beyond the rest's
            rho0 = s.mat[s.Si[q.material, i], rho0_col]
            if ti.static(not density):
                if f.count[i] < s.params[p["dfsph_min_neighbours"]]:
                    residual = 0.0  # too few neighbours for a divergence (a splash)
            # the error: compression, and expansion where the pressure is positive
            # (there the density must be rho0 both ways; at zero pressure, as at a
            # free surface, a lower density is allowed)
            compression = ti.max(residual, 0.0) / rho0
            if s.Ss[row, i] > 0.0:
                compression = ti.abs(residual) / rho0
            if dt > 0.0:  # projected Jacobi: a pressure may fall, not below zero
                k_old = s.Ss[row, i]
                k_new = ti.max(0.0, k_old + s.params[p["dfsph_relaxation"]] * residual
                               * s.Ss[q.alpha, i] / scale)
                if ti.static(density):
                    # Chebyshev semi-iteration (weight w > 1, set by the host; 0 or 1: plain
                    # Jacobi): the new pressure over-shoots along the last two iterates' direction
                    if weight > 1.0:
                        previous = s.Ss[q.kappa_prev, i]
                        k_new = ti.max(0.0, previous + weight * (k_new - previous))
                    s.Ss[q.kappa_prev, i] = k_old
                s.Ss[row, i] = k_new
            if ti.static(not density):
                compression *= dt
            return compression

        return update

    # --- the non-pressure forces and the first density iteration ----------------------------
    def _non_pressure(self):
        """ti.func(s, i, dt) -> v*_i + dt a_i(k): step 3 for fluid particle i (its non-pressure
        forces, v* = v + dt a and the XSPH shift; the density beyond the rest density, the
        density solve's source, which a particle short of it, as at a free surface, keeps at
        zero: it must not be compressed either), in the same walk of i's pair list as the
        first density iteration's pressure acceleration a_i(k) (docs/dfsph.md, "Where the
        time goes"). Each sum runs in the order of the list, as in a walk of its own."""
        solver = self.solver
        q, grid, f = self.q, self.grid, self.x.pairs
        dim, real = self.dim, self.real
        p = self.p
        local = self.local
        visitor = NonPressure(solver)
        particle_terms = [t for t in solver.terms if t.has_particle]
        Rates = solver.Rates
        rho0_col = solver.eos.m.rho0
        has_shift = self.has_shift

        @ti.func
        def forces(s_mem: ti.template(), i, dt):
            s = ti.static(s_mem._replace(params=local(s_mem)))
            rates = Rates(acc=ti.Vector.zero(real, dim))
            for t in ti.static(particle_terms):
                ti.static(kernels._traced(t.name, "particle"))
                t.particle(s, i, rates)
            # the force limit of dt follows the body forces (gravity): the viscous
            # terms have their own limit, 0.125 h^2 / nu (timestep.py)
            acc2 = ti.cast(rates.acc.norm_sqr(), ti.f64)
            if acc2 > s.status[st.MAX_ACC2]:
                ti.atomic_max(s.status[st.MAX_ACC2], acc2)
            xi = s.Sv[q.position, i]
            a = -s.Ss[q.kappa, i] * s.Sv[q.gsum, i]
            for k in range(f.count[i]):
                j = f.nbr[i, k]
                rij = grid.separation(s, xi, s.Sv[q.position, j])
                coef = f.coef[i, k]
                visitor.visit(s, i, j, rij, rij.norm_sqr(), coef, rates)
                a -= (coef * s.Ss[q.kappa, j]) * rij
            scale = s.params[p["dfsph_gradient_scale"]]
            a *= scale
            vstar = s.Sv[q.velocity, i] + dt * rates.acc
            s.Sv[q.vstar, i] = vstar
            if ti.static(has_shift):
                s.Sv[q.shift, i] = rates.shift
            rest = s.mat[s.Si[q.material, i], rho0_col] * s.params[p["dfsph_rest_ratio"]]
            s.Ss[q.source, i] = ti.max(s.Ss[q.density, i] - rest, 0.0)
            return vstar + dt * a

        return forces

    # --- between the solves ---------------------------------------------------------------
    def middle(self):
        """v += dt a(kv) (the divergence solve's result) and the walls' no-slip velocity,
        which the non-pressure forces of the first density iteration use (:meth:`_non_pressure`)."""
        q = self.q
        real = self.real
        p = self.p
        x = self.x
        acceleration = self._acceleration()
        wall_velocity = self.wall_velocity

        @ti.func
        def body(s_mem: ti.template(), t_target):
            dt = ti.cast(s_mem.status[st.DT], real)
            skipped = x.result[1] <= s_mem.params[p["dfsph_divergence_tolerance"]]  # no divergence solve
            for i in range(s_mem.sizes[st.N_PARTICLES]):
                if s_mem.Si[q.kind, i] == FLUID:
                    if skipped:
                        s_mem.Ss[q.kappa_v, i] = 0.0
                    else:
                        s_mem.Sv[q.velocity, i] += dt * acceleration(s_mem, i, q.kappa_v)
            if ti.static(wall_velocity):
                # no-slip velocity of the walls (Adami et al. 2012 eq. 22-23), from the sums
                # gathered in step 1: v_w = 2 v_wall - sum_f v_f W_wf / sum_f W_wf
                for i in range(s_mem.sizes[st.N_PARTICLES]):
                    if s_mem.Si[q.kind, i] == WALL:
                        ghost = s_mem.Sv[q.velocity, i]
                        weight = s_mem.Ss[q.wall_weight, i]
                        if weight > 0.0:
                            ghost = 2.0 * ghost - s_mem.Sv[q.wall_velocity, i] / weight
                        s_mem.Sv[q.wall_velocity, i] = ghost

        return body

    # --- step 5 ------------------------------------------------------------------------
    def final(self):
        """v = v* + dt a(k), x += dt v; the state back to C; pressure; maxima; guards."""
        solver = self.solver
        q = self.q
        copy = kernels.copy_rows(solver)
        real = self.real
        integ, guards = solver.integrator, solver.guards
        acceleration = self._acceleration()
        Rates = solver.Rates
        has_shift = self.has_shift
        local = self.local

        @ti.func
        def body(s_mem: ti.template(), t_target):
            dt = ti.cast(s_mem.status[st.DT], real)
            for i in range(s_mem.sizes[st.N_PARTICLES]):
                s = ti.static(s_mem._replace(params=local(s_mem)))
                copy(s.S, i, s.C, i)
                kind = s.Si[q.kind, i]
                if kind == FLUID:
                    a = acceleration(s, i, q.kappa)
                    v = s.Sv[q.vstar, i] + dt * a
                    u = v
                    if ti.static(has_shift):
                        u += s.Sv[q.shift, i]
                    s.Cv[q.position, i] = s.Sv[q.position, i] + dt * u
                    s.Cv[q.velocity, i] = v
                    rho = s.Ss[q.density, i]
                    # both solves applied pressure accelerations this step: v += dt a(kv), then
                    # dt a(k); a is linear in the pressures, so the step's pressure is k + kv
                    s.Cs[q.pressure, i] = (s.Ss[q.kappa, i] + s.Ss[q.kappa_v, i]) * rho * rho
                    speed = ti.cast(v.norm(), ti.f64)
                    if speed > s.status[st.MAX_SIGNAL]:
                        ti.atomic_max(s.status[st.MAX_SIGNAL], speed)
                    rates = Rates(acc=a)
                    guards.check(s, i, rates)
                elif kind == WALL:
                    s.Cs[q.pressure, i] = 0.0
                    integ.advance_wall(s, i, dt)

        return body

