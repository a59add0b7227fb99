"""The probes' sums on the device: one auxiliary kernel per solver, run after a step.

It reads the cell-sorted state ``S`` of the last step (the state the step's rates were
computed from; see :mod:`taisph.probes` for why) and, in one parallel loop (one wake
of the thread pool), computes

- for every sample point x_k (pressure and flow probes, and the points of the
  elevation probes' vertical lines) the kernel sums over fluid particles j within the
  support,

      phi_k = sum_j V_j W(x_k - x_j, h),      pi_k = sum_j p_j V_j W(x_k - x_j, h),
      u_k = sum_j v_j V_j W(x_k - x_j, h),    V_j = m_j / rho_j;

- for every wall particle w of a force probe's wall group, minus the force its
  neighbours' momentum equations get from it through the pressure terms (pressure
  gradient, Hu-Adams pressure, the Riemann formulation's, Lennard-Jones wall force) and
  the viscosity terms that act at walls (laminar and artificial viscosity with
  ``walls=True``: the shear force; :data:`FORCE_TERMS`),

      F_w = - sum_{fluid f} m_f a_f<-w,

  with a_f<-w exactly what that term's ``pair(f, w)`` adds to ``dv_f/dt`` in the force
  pass; F = sum_w F_w over the group (atomic adds: the last bits of F depend on the
  thread order). Under DFSPH, which replaces those terms by its pressure solves
  (:mod:`taisph.engine.dfsph.solver`), a_f<-w is the wall's share of DFSPH's momentum
  equation with the step's pressures (k = kappa + kappa_v = p / rho^2, both solves'; the
  wall mirrors p_f and adds its hydrostatic head, p_w = p_f + rho_f g . (x_w - x_f)):

      a_f<-w = - s (phi k_f - g . r_fw / rho_f) m_w grad_f W_fw,    phi = WALL_MIRROR (2),

  s the solve's pressure force factor (``dfsph_gradient_scale``, 1 / the lattice's
  gradient moment).

Inputs go in through the auxiliary kernel's two ndarray arguments, which this module
allocates once per :class:`Sampler`:

``aux_real[k, :]``   point k: ``x (dim), active (0/1), phi, pi, u (dim)`` (the last three written);
                     then one row per force group: ``F (dim)`` (written; zeroed before);
``aux_int[0, :]``    ``n_points, n_groups, n_ranges, 0``;
``aux_int[1 + r, :]``  id range r of the force groups: ``first id, end id, group, active``.

Neighbours are found by walking the cells of the neighbour grid around x (the
cells and the order of ``S`` are those of the last sort; with neighbour lists, those
of the last rebuild, whose cells are one list skin larger than the kernel support:
a particle within the support now was within it plus half the skin then, so the
walk is exact there too).
"""


import weakref

import numpy as np
import taichi as ti

from ..engine import status as st
from ..engine.dfsph.kernels import WALL_MIRROR
from ..engine.layout import FLUID, VARIABLE_H, WALL
from ..messages import InputError

# terms whose wall contributions make up a force probe: the pressure force of the
# fluid on the wall (and, for Lennard-Jones walls, their repulsion, which stands in for it)
# and the viscous (shear) force of the viscosity terms that act between fluid and walls
# (walls=True; without it their pair skips wall particles and adds nothing)
FORCE_TERMS = ("pressure", "pressure_hu_adams", "riemann", "lennard_jones_wall", "laminar_viscosity",
               "artificial_viscosity")

_builders = weakref.WeakKeyDictionary()  # solver -> the kernel builder of its probes


def probe_kernel(solver):
    """The builder of `solver`'s probe kernel (:meth:`Solver.make_aux_kernel`): the
    kernel compiles once per field set and takes the two auxiliary arrays and the time."""
    builder = _builders.get(solver)
    if builder is None:
        builder = _builders[solver] = solver.make_aux_kernel(_body(solver))
    return builder


def _body(solver):
    """The probe kernel's body: one parallel loop over the sample points and the particles
    (the rows of ``aux_real`` and ``aux_int``: the module's docstring)."""
    q = solver.layout.q
    dim = solver.dim
    if getattr(q, VARIABLE_H, -1) >= 0:
        raise InputError("probes interpolate with the scene's constant smoothing length; this scene varies h "
                         "per particle (adaptive_h), which probes do not support")
    p_support2 = solver.param_rows["support2"]
    point_sums = _point_sums(solver)
    wall_force = _wall_force(solver)
    ACTIVE = dim  # column of a point's row: 1 if it is sampled

    @ti.func
    def body(s: ti.template(), t_target):
        n_points = s.aux_int[0, 0]
        n_ranges = s.aux_int[0, 2]
        support2 = s.params[p_support2]
        ti.loop_config(serialize=True)
        for g in range(s.aux_int[0, 1]):  # the force rows accumulate: zero them first
            for d in ti.static(range(dim)):
                s.aux_real[n_points + g, d] = 0.0
        for k in range(n_points + s.sizes[st.N_PARTICLES]):
            if k < n_points:
                if s.aux_real[k, ACTIVE] > 0.0:
                    point_sums(s, k, support2)
            else:
                w = k - n_points
                if s.Si[q.kind, w] == WALL:
                    ident = s.Si[q.id, w]
                    for r in range(n_ranges):
                        row = 1 + r
                        if s.aux_int[row, 3] > 0 and s.aux_int[row, 0] <= ident < s.aux_int[row, 1]:
                            force = wall_force(s, w, support2)
                            for d in ti.static(range(dim)):
                                ti.atomic_add(s.aux_real[n_points + s.aux_int[row, 2], d], force[d])

    return body


def _point_sums(solver):
    """The ``ti.func`` ``point_sums(s, k, support2)``: the kernel sums phi, pi and u at
    sample point k over the fluid particles within the support (the module's docstring),
    written to the point's row."""
    q = solver.layout.q
    grid, kern, dim, real = solver.grid, solver.kernel, solver.dim, solver.real
    rows = solver.param_rows
    p_inv_h, p_w_norm = rows["inv_h"], rows["w_norm"]
    PHI, PI, U = dim + 1, dim + 2, dim + 3  # columns of a point's row (U: dim of them)

    @ti.func
    def point_sums(s: ti.template(), k, support2):
        x = ti.Vector([s.aux_real[k, d] for d in ti.static(range(dim))], dt=real)
        phi = ti.cast(0.0, real)
        pi = ti.cast(0.0, real)
        u = ti.Vector.zero(real, dim)
        c = grid.coords(s, x)
        for r in range(grid.n_ranges):
            begin, end = grid.slot_range(s, c, r)
            for j in range(begin, end):
                if s.Si[q.kind, j] == FLUID:
                    rij = grid.separation(s, x, s.Sv[q.position, j])
                    r2 = rij.norm_sqr()
                    if r2 < support2:
                        w = s.params[p_w_norm] * kern.f(ti.sqrt(r2) * s.params[p_inv_h])
                        vw = s.Ss[q.mass, j] / s.Ss[q.density, j] * w
                        phi += vw
                        pi += s.Ss[q.pressure, j] * vw
                        u += s.Sv[q.velocity, j] * vw
        s.aux_real[k, PHI] = phi
        s.aux_real[k, PI] = pi
        for d in ti.static(range(dim)):
            s.aux_real[k, U + d] = u[d]

    return point_sums


def _wall_force(solver):
    """The ``ti.func`` ``wall_force(s, w, support2)``: the force of the fluid on wall
    particle w through the :data:`FORCE_TERMS` (under DFSPH its pressure's; the module's
    docstring)."""
    q = solver.layout.q
    grid, kern, dim, real = solver.grid, solver.kernel, solver.dim, solver.real
    rows = solver.param_rows
    p_inv_h, p_grad_norm = rows["inv_h"], rows["grad_norm"]
    force_terms = [t for t in solver.terms if t.name in FORCE_TERMS and t.has_pair]
    dfsph = solver.method.name == "dfsph"  # its pressure force on a wall: dfsph_pressure_force
    p_gravity = rows.get("gravity", -1)
    p_scale = rows.get("dfsph_gradient_scale", -1)  # DFSPH's pressure force factor (engine/dfsph/parameters.py)
    Rates = solver.Rates

    @ti.func
    def dfsph_pressure_force(s: ti.template(), f, w, rfw, grad):
        """a_f<-w of DFSPH (the module's docstring): the step's pressures of the sorted
        state (both solves', as in the pressure written at the end of a step), the wall's
        mirrored pressure and hydrostatic head (engine/dfsph/kernels.py, visitors.py)."""
        coef = s.Ss[q.mass, w] * grad
        share = WALL_MIRROR * (s.Ss[q.kappa, f] + s.Ss[q.kappa_v, f])
        if ti.static(p_gravity >= 0):
            g = ti.Vector([s.params[p_gravity + d] for d in ti.static(range(dim))])
            share -= g.dot(rfw) / s.Ss[q.density, f]
        return -(s.params[p_scale] * share) * coef

    @ti.func
    def wall_force(s: ti.template(), w, support2):
        """Minus the pressure terms' (DFSPH: its pressure's) accelerations of w's fluid
        neighbours due to w, times their masses: the force of the fluid on wall particle w."""
        xw = s.Sv[q.position, w]
        force = ti.Vector.zero(real, dim)
        c = grid.coords(s, xw)
        for r in range(grid.n_ranges):
            begin, end = grid.slot_range(s, c, r)
            for f in range(begin, end):
                if s.Si[q.kind, f] == FLUID:
                    rfw = grid.separation(s, s.Sv[q.position, f], xw)
                    r2 = rfw.norm_sqr()
                    if r2 < support2:
                        dist = ti.sqrt(r2)
                        grad = (s.params[p_grad_norm] * kern.g(dist * s.params[p_inv_h])) * rfw
                        rates = Rates(acc=ti.Vector.zero(real, dim))
                        if ti.static(dfsph):
                            rates.acc = dfsph_pressure_force(s, f, w, rfw, grad)
                        for t in ti.static(force_terms):
                            t.pair(s, f, w, rfw, dist, grad, rates)
                        force -= s.Ss[q.mass, f] * rates.acc
        return force

    return wall_force


class Sampler:
    """The device side of a set of probes for one simulation: sample points and force
    groups uploaded once; :meth:`sums` runs the kernel and returns the sums.

    `points`: (P, dim) sample points; `groups`: one array of particle ids per force
    group (converted to contiguous id ranges)."""

    def __init__(self, sim, points, groups):
        self.sim = sim
        self.dim = dim = sim.dim
        self.n_points = len(points)
        self.n_groups = len(groups)
        self.builder = probe_kernel(sim.solver)
        self._uploaded = None  # the active points and groups last uploaded
        self.ranges = [(a, b, g) for g, ids in enumerate(groups) for a, b in id_ranges(ids)]
        real = sim.state.runtime.numpy_real
        self.inputs = np.zeros((self.n_points + self.n_groups, 2 * dim + 3), real)
        self.inputs[: self.n_points, :dim] = np.asarray(points, float).reshape(-1, dim)
        ints = np.zeros((1 + len(self.ranges), 4), np.int32)
        ints[0, :3] = self.n_points, self.n_groups, len(self.ranges)
        if self.ranges:
            ints[1:, :3] = np.asarray(self.ranges)
        self.ints = ints
        self.aux_real = ti.ndarray(sim.state.runtime.real, self.inputs.shape)
        self.aux_int = ti.ndarray(ti.i32, ints.shape)

    def sums(self, points_active, groups_active, time):
        """Run the kernel on the state ``S`` now; `points_active` (P bools) and
        `groups_active` (G bools) say what to compute. Returns ``(phi, pi, u, forces)``:
        (P,), (P,), (P, dim) and (G, dim) arrays (stale where inactive). The inputs are uploaded
        only when the active ones change (an upload is a host-to-device copy; its cost: docs/scenes.md)."""
        key = (np.packbits(points_active).tobytes(), np.packbits(groups_active).tobytes())
        if key != self._uploaded:
            self.inputs[: self.n_points, self.dim] = points_active
            self.ints[1:, 3] = [groups_active[g] for _, _, g in self.ranges]
            self.aux_real.from_numpy(self.inputs)
            self.aux_int.from_numpy(self.ints)
            self._uploaded = key
        kernel = self.sim.state.fields.kernel(("probes", self.builder), self.builder)
        kernel(self.aux_int, self.aux_real, float(time))
        out = self.aux_real.to_numpy()
        P, d = self.n_points, self.dim
        return (out[:P, d + 1].astype(float), out[:P, d + 2].astype(float), out[:P, d + 3 :].astype(float),
                out[P:, :d].astype(float))

    def free(self):
        from ..engine import runtime

        if runtime.is_current(self.sim.runtime):
            for array in (self.aux_real, self.aux_int):
                runtime.free_ndarray(array)


def id_ranges(ids) -> list:
    """Contiguous ``[first, end)`` ranges covering the particle ids `ids` (a slice,
    range, boolean mask or integer array)."""
    if isinstance(ids, slice):
        ids = range(ids.start or 0, ids.stop, ids.step or 1)
    ids = np.asarray(ids)
    if ids.dtype == bool:
        ids = np.flatnonzero(ids)
    ids = np.unique(ids.astype(np.int64))
    if len(ids) == 0:
        return []
    breaks = np.flatnonzero(np.diff(ids) != 1)
    starts = np.concatenate([[ids[0]], ids[breaks + 1]])
    ends = np.concatenate([ids[breaks] + 1, [ids[-1] + 1]])
    return list(zip(starts.tolist(), ends.tolist()))
