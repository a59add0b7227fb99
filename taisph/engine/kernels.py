"""What each kernel of a step does: the kernel bodies, assembled at compile time.

A step is three kinds of kernel launch, issued one after another by the host without
reading anything back (each parallel loop wakes the CPU thread pool, a fixed cost, so
work is fused into as few passes as possible; docs/performance.md):

``sort``    :func:`sort_body`. The time step is chosen (serial; :mod:`.timestep`);
            each particle's cell is computed at the position its rates will be
            evaluated at (the integrator's predictor) and counted, a serial prefix sum
            over the cells gives each cell's first slot, and each particle's whole
            state is scattered from ``C`` to its cell-sorted slot in ``S``
            (:mod:`.neighbours`). The integrator's predictor, periodic wrapping, the
            equation of state and the terms' per-particle ``derive`` run in the same
            loop. With neighbour lists the scatter keeps the order between rebuilds.
``passes``  :func:`pass_body`, only if a term needs them: neighbour sums that must be
            complete before the rates (wall pressure extrapolated from the fluid,
            summation density), one launch each, in the order the terms list them.
``force``   :func:`force_body`. For every fluid particle: the terms' ``particle``
            contributions, then the sum of their ``pair`` contributions over its
            neighbours (``ti.static`` loop over the terms: an unlisted term has no
            code), the integrator's update into ``C``, the maxima for the next dt and
            the guards. Wall particles move rigidly.

Every body is a ``ti.func(s, t_target)`` over the fields ``s`` of a simulation
(:class:`taisph.engine.assembly.Args`); :meth:`Solver.make_kernel` compiles it into a
kernel that binds the fields and takes only ``t_target``.
"""

import taichi as ti

from . import status as st
from .layout import FLUID, VARIABLE_H, WALL

# (term, role) of every term function traced into a kernel, added at compile time: proof
# that a term the scene does not list contributes no code (tests/test_effects.py). A set,
# so it holds each pair once however many kernels compile (clear it to watch a build).
TRACED: set = set()
SELECT = {"fluid": FLUID, "wall": WALL, "all": -1}


def _traced(name: str, role: str):
    TRACED.add((name, role))


@ti.data_oriented
class _ForceSum:
    """Neighbour visitor of the force pass: kernel gradient once, then every pair term."""

    def __init__(self, solver, pair_terms):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.terms = pair_terms
        self.p_inv_h = solver.param_rows["inv_h"]
        self.p_grad_norm = solver.param_rows["grad_norm"]
        self.h_row = getattr(self.q, VARIABLE_H, -1)
        self.h_varies = self.h_row >= 0  # compile time: is h per particle?

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, rates: ti.template()):
        r = ti.sqrt(r2)
        grad = rij
        if ti.static(not self.h_varies):
            grad = (s.params[self.p_grad_norm] * self.kern.g(r * s.params[self.p_inv_h])) * rij
        else:
            # variable h: the mean of both particles' kernel gradients (Hernquist &
            # Katz 1989), antisymmetric in i, j, so pair forces stay equal and opposite
            hi, hj = s.Ss[self.h_row, i], s.Ss[self.h_row, j]
            grad = (0.5 * (self.kern.grad_factor_h(r, hi) + self.kern.grad_factor_h(r, hj))) * rij
        for t in ti.static(self.terms):
            ti.static(_traced(t.name, "pair"))
            t.pair(s, i, j, rij, r, grad, rates)


@ti.data_oriented
class _PassSum:
    """Neighbour visitor of a pre-force pass: kernel value and gradient, then the pass."""

    def __init__(self, solver, neighbour_pass):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.p = neighbour_pass
        self.p_inv_h = solver.param_rows["inv_h"]
        self.p_w_norm = solver.param_rows["w_norm"]
        self.p_grad_norm = solver.param_rows["grad_norm"]
        self.h_row = getattr(self.q, VARIABLE_H, -1)
        self.h_varies = self.h_row >= 0

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        r = ti.sqrt(r2)
        w = r
        grad = rij
        if ti.static(not self.h_varies):
            q = r * s.params[self.p_inv_h]
            w = s.params[self.p_w_norm] * self.kern.f(q)
            grad = (s.params[self.p_grad_norm] * self.kern.g(q)) * rij
        else:  # variable h: particle i's own smoothing length (a gather sum)
            hi = s.Ss[self.h_row, i]
            w = self.kern.w_h(r, hi)
            grad = self.kern.grad_factor_h(r, hi) * rij
        ti.static(_traced(self.p.owner, "pass"))
        self.p.pair(s, i, j, rij, r, w, grad, acc)


def _local_parameters(solver):
    """A ti.func(s) -> s with ``params`` read into registers: inside a particle's loop
    body every term reads its parameters from there, so the pair loop reloads none of
    them from memory (with other arrays written in the same kernel, the compiler must
    assume a store may change the parameter array, and reloads it for every pair).

    The vector must be assigned to a local variable: returned as an expression, Taichi
    inlines the element loads at every use, inside the pair loop (docs/performance.md)."""
    n_params = solver.n_params

    @ti.func
    def local(s: ti.template()):
        values = ti.Vector([s.params[k] for k in ti.static(range(n_params))])
        return values

    return local


def copy_rows(solver):
    """A ti.func(source, i, target, j): the carried rows of particle i of `source` to slot
    j of `target`, each the :class:`~taisph.engine.assembly.Buffers` of a state."""
    carried_v, carried_s, carried_i = solver.layout.carried

    @ti.func
    def copy(source: ti.template(), i, target: ti.template(), j):
        for k in ti.static(carried_v):
            target.v[k, j] = source.v[k, i]
        for k in ti.static(carried_s):
            target.s[k, j] = source.s[k, i]
        for k in ti.static(carried_i):
            target.i[k, j] = source.i[k, i]

    return copy


def derive_all(solver):
    """A ti.func(s, i): the equation of state and the terms' ``derive`` for particle i."""
    eos = solver.eos
    # one call per distinct hook: terms sharing one (taisph.terms.base.VolumeTerm) write the same rows
    hooks = {}
    for t in solver.terms:
        if t.has_derive:
            hooks.setdefault(type(t).derive, t)
    derive_terms = list(hooks.values())

    @ti.func
    def derive(s: ti.template(), i):
        ti.static(_traced(eos.name, "eos"))
        eos.derive(s, i)
        for t in ti.static(derive_terms):
            ti.static(_traced(t.name, "derive"))
            t.derive(s, i)

    return derive


@ti.func
def _idle(s: ti.template()) -> bool:
    """Is this launch idle (the clock already stands at the target;
    :meth:`taisph.engine.timestep.TimeStep.begin_step`)? Then it changes nothing."""
    return s.status[st.IDLE] > 0.0


@ti.func
def _particles(s: ti.template()):
    """How many particles this launch works on: none if it is idle."""
    n = s.sizes[st.N_PARTICLES]
    if _idle(s):
        n = 0
    return n


def sort_body(solver, serial: bool):
    """dt, predictor, counting sort, scatter C -> S, equation of state (see above)."""
    q = solver.layout.q
    copy = copy_rows(solver)
    grid, integ, timestep = solver.grid, solver.integrator, solver.timestep
    derive = derive_all(solver)
    real = solver.real

    @ti.func
    def body(s: ti.template(), t_target):
        ti.loop_config(serialize=True)
        for _ in range(1):
            timestep.begin_step(s, t_target)
        n = _particles(s)
        dt = ti.cast(s.status[st.DT], real)
        ti.loop_config(serialize=serial)
        for i in range(n):
            # x: where this step's rates are evaluated
            x = grid.wrap(s, integ.predicted_position(s, i, dt))
            grid.note_displacement(s, i, x)
            grid.count(s, i, x)
        ti.loop_config(serialize=True)
        for _ in range(1):
            if not _idle(s):
                grid.scan(s)
        rebuild = grid.rebuilding(s)
        ti.loop_config(serialize=serial)
        for i in range(n):
            slot = grid.slot(s, i, rebuild)
            copy(s.C, i, s.S, slot)
            integ.predict(s, i, slot, dt)
            if ti.static(grid.any_periodic):
                s.Sv[q.position, slot] = grid.wrap(s, s.Sv[q.position, slot])
            if ti.static(grid.lists):
                if rebuild:
                    s.x_ref[slot] = s.Sv[q.position, slot]
            derive(s, slot)

    return body


def pass_body(solver, neighbour_pass):
    """One pre-force neighbour sum over the selected particles (see above)."""
    q = solver.layout.q
    grid = solver.grid
    derive = derive_all(solver)
    visitor = _PassSum(solver, neighbour_pass)
    select = SELECT[neighbour_pass.select]
    p_support2 = solver.param_rows["support2"]
    local_parameters = _local_parameters(solver)

    @ti.func
    def body(s_mem: ti.template(), t_target):
        n = _particles(s_mem)
        for i in range(n):
            if ti.static(select < 0) or s_mem.Si[q.kind, i] == select:
                s = ti.static(s_mem._replace(params=local_parameters(s_mem)))
                acc = neighbour_pass.init(s, i)
                grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p_support2], visitor, acc)
                neighbour_pass.finish(s, i, acc)
                if ti.static(neighbour_pass.rederive):
                    derive(s, i)

    return body


def force_body(solver):
    """Rates of every fluid particle, the integrator's update, dt maxima, guards."""
    q = solver.layout.q
    copy = copy_rows(solver)
    real, dim = solver.real, solver.dim
    grid, integ, timestep, guards = solver.grid, solver.integrator, solver.timestep, solver.guards
    visitor = _ForceSum(solver, [t for t in solver.terms if t.has_pair])
    particle_terms = [t for t in solver.terms if t.has_particle]
    finish_terms = [t for t in solver.terms if t.has_finish]
    Rates = solver.Rates
    p_support2 = solver.param_rows["support2"]
    local_parameters = _local_parameters(solver)
    imposed = solver.imposed_rows  # compile time: rows of particles a term imposes (Term.imposed_row)

    @ti.func
    def body(s_mem: ti.template(), t_target):
        dt = ti.cast(s_mem.status[st.DT], real)
        n = _particles(s_mem)
        for i in range(n):
            s = ti.static(s_mem._replace(params=local_parameters(s_mem)))
            copy(s.S, i, s.C, i)  # the integrator then writes what it advances
            buffer = False  # a particle a term imposes (Term.imposed_row): moves with its own velocity
            for row in ti.static(imposed):
                if s.Si[row, i] > 0:
                    buffer = True
            if buffer:
                integ.advance_wall(s, i, dt)
            elif s.Si[q.kind, i] == FLUID:
                rates = Rates(acc=ti.Vector.zero(real, dim))  # other members zero-initialised
                for t in ti.static(particle_terms):
                    ti.static(_traced(t.name, "particle"))
                    t.particle(s, i, rates)
                grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p_support2], visitor, rates)
                for t in ti.static(finish_terms):
                    ti.static(_traced(t.name, "finish"))
                    t.finish(s, i, rates)
                integ.update(s, i, rates, dt)
                timestep.track(s, i, rates)
                guards.check(s, i, rates)
            elif s.Si[q.kind, i] == WALL:
                integ.advance_wall(s, i, dt)
            # removed particles: carried over unchanged

    return body


def copy_body(solver, source, target):
    """Copy the carried rows of the particles in use from `source` to `target`
    (:class:`~taisph.engine.assembly.Buffers`): the last good state."""
    copy = copy_rows(solver)

    @ti.func
    def body(s: ti.template(), t_target):
        for i in range(s.sizes[st.N_PARTICLES]):
            copy(source, i, target, i)

    return body


def pressure_body(solver):
    """The equation of state (and derived quantities) of the state in ``C`` (or any
    buffers passed as ``C``), in place: pressure for output."""
    derive = derive_all(solver)

    @ti.func
    def body(s: ti.template(), t_target):
        c = ti.static(s.with_S(s.C))  # here the "sorted" arrays are C
        for i in range(s.sizes[st.N_PARTICLES]):
            derive(c, i)

    return body


@ti.data_oriented
class _CountPairs:
    def __init__(self, q):
        self.q = q

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        acc += 1


@ti.data_oriented
class _ListPairs(_CountPairs):
    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        s.aux_int[i, acc] = s.Si[self.q.id, j]
        acc += 1


def pairs_body(solver, fill: bool):
    """For tests of the neighbour search: the neighbours the sums visit, for every
    particle of ``S``; their number into ``aux_int[i, 0]`` (`fill` False) or their ids
    into ``aux_int[i, :]`` (`fill` True)."""
    q = solver.layout.q
    grid = solver.grid
    p_support2 = solver.param_rows["support2"]
    visitor = _ListPairs(q) if fill else _CountPairs(q)

    @ti.func
    def body(s: ti.template(), t_target):
        for i in range(s.sizes[st.N_PARTICLES]):
            k = 0
            grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p_support2], visitor, k)
            if ti.static(not fill):
                s.aux_int[i, 0] = k

    return body
