"""DFSPH: divergence-free SPH, an implicit incompressible solver (``Scene(solver="dfsph")``).

Bender & Koschier, "Divergence-free smoothed particle hydrodynamics", SCA 2015, and
"Divergence-free SPH for incompressible and viscous fluids", IEEE TVCG 23(3), 2017
(BK17); the pressure iterations in the form of Koschier, Bender, Solenthaler &
Teschner, "Smoothed particle hydrodynamics techniques for the physics based
simulation of fluids and solids", Eurographics tutorial 2019, sec. 3.3 (pressure
values accumulated, so that they can be warm-started). Instead of an equation of
state, a pressure is solved for every step that keeps the density at rho0.

One step (time step dt, all sums over neighbours j closer than the support radius,
fluid and wall particles; ``g_ij = m_j grad_i W_ij``):

1. density by summation and the factor of every fluid particle i (BK17 eq. 11),

       rho_i = sum_j m_j W_ij,
       D_i   = (sum_j g_ij) . (sum_fluid g_ij + phi sum_wall g_ij) + sum_fluid |g_ij|^2,   alpha_i = 1 / D_i,

   and the pair list (:mod:`.pairs`); D_i is how the density change of i answers
   its own pressure (for equal masses), phi the wall's share (below);
2. the divergence-free solve (BK17 algorithm 2): pressures kv_i such that the
   velocities v + dt a(kv) have D rho/Dt = sum_j g_ij . (v_i - v_j) <= 0, where

       a_i(k) = - sum_fluid g_ij (k_i + k_j) - phi k_i sum_wall g_ij          (k = p / rho^2)

   (walls mirror the pressure of the fluid particle, p_wall = p_i; every pressure force,
   this one and the walls' head below, is scaled by 1 / B, B the gradient moment of the
   lattice, :func:`.parameters.gradient_scale`, so that water at rest has the hydrostatic
   pressure); then v += dt a(kv);
3. the non-pressure forces, the scene's terms that make sense without an equation of
   state (gravity, laminar and artificial viscosity, XSPH; :data:`taisph.scene.solvers.DFSPH_KEPT`), and the
   hydrostatic head of the walls: a mirrored wall particle b has the pressure
   p_i + rho_i g . (x_b - x_i) (Adami et al. 2012 eq. 27), whose part beyond p_i is
   known, a_i += sum_wall g_ib (g . r_ib) / rho_i; and fluid pairs closer than dx repel
   (:data:`.visitors.PAIRING_REPULSION`: the pairing instability). Then v* = v + dt a_nonpressure
   (summed in the first density iteration's walk of the pair list: one walk less);
4. the constant-density solve (BK17 algorithm 3): pressures k_i such that the
   predicted density rho*_i + dt^2 sum_j g_ij . (a_i(k) - a_j(k)), with
   rho*_i = rho_i + dt sum_j g_ij . (v*_i - v*_j), is <= rho0;
5. v = v* + dt a(k), x += dt v (symplectic Euler; + dt times the XSPH shift).

Both solves are Jacobi iterations: each iteration computes a(k) for every particle
(one pass over the pairs) and then the residual r_i and the update (another pass),

       k_i <- max(0, k_i + omega r_i / (dt^n D_i)),     n = 1 (divergence), 2 (density),

omega = min(0.5, 2.3 / sqrt(neighbours)) (:func:`relaxation`: 0.5 in 2D, 0.27 in
3D with h = 1.3 dx; a projected Jacobi iteration: pressures may fall, never below zero;
a density solve that runs past 8 iterations is Chebyshev-accelerated, :mod:`.chebyshev`), r_i
the predicted density rate (divergence) or the predicted density minus the rest
density (the lattice's, :func:`lattice_ratio`; a particle short of it, as at a free
surface, must keep its density instead); an iteration is one kernel launch, and the
host reads the mean error (one f64) to decide whether to stop (:class:`Stepper`): the
mean over fluid particles of |r_i| where the pressure is positive, max(r_i, 0)
elsewhere, times dt / rho0 (divergence) or over rho0 (density), against the
tolerances ``dfsph_divergence_tolerance`` (0.1 %) and ``dfsph_tolerance`` (0.02 %),
with at least ``dfsph_min_iterations`` (2) density iterations and at most
``dfsph_max_iterations`` (300) of either; the divergence solve is skipped when its
error is within the tolerance before any iteration. A solve that reaches the maximum
above its tolerance but within ``dfsph_error_bound`` (10) times it is kept and counted
(:class:`Stats`: ``above_tolerance``, the worst error over its tolerance); beyond that it
stops the run through the guards (``UNCONVERGED``, :mod:`taisph.engine.diagnosis` with
:mod:`.diagnosis`).
Each solve starts from the last step's pressures (warm start, BK17 sec. 4.3; the first
from the scene's initial pressure, :func:`initial_kappa`). Particles with fewer than
7 (2D) or 20 (3D) neighbours (splashes) get no divergence correction. The measured
choices behind each of these, and the alternatives measured, are in docs/dfsph.md; the
chosen ones are compiled in (:mod:`.kernels`), the values derived per scene are the
runtime parameters :data:`PARAMS`.

The time step: dt = min(C h / max|v|, 0.1 sqrt(h / |g|), 0.125 h^2 / nu, dt_max)
(:mod:`.timestep`, the same formula as the weakly compressible step with the signal
speed |v| in place of c + |v|, the body forces as the acceleration, and nu the largest
of the laminar viscosity and the artificial viscosity's alpha h c0 / (2 (d + 2))),
C = 0.5 by default (:data:`.method.DFSPH_COURANT`, 0.65 dx, where BK17 use 0.4 particle
diameters; the ``courant`` control), the force factor 0.1 (:data:`.method.DFSPH_FORCE_FACTOR`).

Walls are particles that carry a volume, m_b / rho0 (their mass as given: the
lattice of the tank's three layers dx apart has the fluid's volume per particle),
in the density sum; the choice and its measurements are in docs/dfsph.md.
"""


import collections
from dataclasses import dataclass, field

import numpy as np
import taichi as ti

from .. import kernels
from .. import status as st
from ...eos import tait
from ..layout import FLUID
from .chebyshev import Chebyshev
# the runtime parameters of the solve, derived per scene (re-exported: the docstring above names them)
from .parameters import (MIN_NEIGHBOURS, PARAMS, artificial_viscosity_nu, gradient_scale,  # noqa: F401
                         lattice_ratio, parameter_values, relaxation)
from .kernels import CHUNKS, StepKernels  # noqa: F401 (CHUNKS: the size of the error sums' field)

Extra = collections.namedtuple("Extra", "pairs part result")  # a field set's DFSPH fields (Solver.extra_fields)


@ti.data_oriented
class Incompressible:
    """What DFSPH has instead of an equation of state: the material table of the Tait
    equation (rho0 for the solve and the guards, c0 for artificial viscosity) and no
    pressure code. The pressure is the solve's, written at the end of every step."""

    name = "incompressible"
    columns = tait.Tait.columns
    scalars = ()
    derived = ()
    outputs = ()

    def material_row(self, material) -> list:
        return tait.Tait().material_row(material)

    def bind(self, layout, material_cols):
        bound = Incompressible()
        bound.q, bound.m = layout.q, material_cols
        return bound

    def compile_key(self):
        return ("incompressible",)

    @ti.func
    def derive(self, s: ti.template(), i):
        pass

    @ti.func
    def sound_speed(self, s: ti.template(), i):
        return s.mat[s.Si[self.q.material, i], self.m.c0]


def rows(has_shift: bool, wall_velocity: bool):
    """(vectors, scalars, derived) DFSPH stores per particle: the pressures k and kv
    (carried: the warm start), the factor, the solve's source, the pressure
    acceleration, the predicted velocity v*, the XSPH shift and the walls' no-slip
    velocity if a kept term needs them."""
    vectors = (["v_pred", "vstar", "gsum"] + (["shift"] if has_shift else [])
               + (["wall_velocity"] if wall_velocity else []))
    scalars = ["kappa", "kappa_v", "kappa_prev", "alpha", "source"] + (["wall_weight"] if wall_velocity else [])
    derived = ["v_pred", "vstar", "gsum", "shift", "wall_velocity", "wall_weight", "alpha", "source", "kappa_prev"]
    return vectors, scalars, derived


def initial_kappa(scene):
    """k = p / rho^2 of the scene's particles at the start, the pressure its Tait
    materials give their initial density (a case that starts in hydrostatic
    equilibrium gives rho0 g depth): the first solve's warm start. Without it the
    first step would have to build the whole pressure field from zero, which takes
    a Jacobi iteration per kernel radius of depth and more (docs/dfsph.md). Zero for
    walls and below zero."""
    rho0 = np.array([m.rho0 for m in scene.materials])[scene.material]
    c0 = np.array([m.c0 for m in scene.materials])[scene.material]
    gamma = np.array([m.gamma for m in scene.materials])[scene.material]
    p = tait.pressure(scene.density, rho0, c0, gamma)
    return np.where(scene.kind == FLUID, np.maximum(p, 0.0) / rho0**2, 0.0)


# --- the host side -----------------------------------------------------------------------
@dataclass
class Stats:
    """Iterations and errors of the solves: totals since the simulation started (each
    simulation has its own: :meth:`Stepper.bind`), and the window of the current run
    (:meth:`Stepper.begin_window`)."""

    steps: int = 0  # steps with dt > 0
    density_iterations: int = 0
    divergence_iterations: int = 0
    round_trips: int = 0  # host reads of the device (the error, once per iteration; dt once per step)
    window_steps: int = 0
    window_density_iterations: int = 0
    window_divergence_iterations: int = 0
    max_density_iterations: int = 0
    max_divergence_iterations: int = 0
    max_density_error: float = 0.0  # the largest error a density solve stopped at (fraction of rho0)
    max_divergence_error: float = 0.0
    last_density_error: float = 0.0
    # steps kept with a solve that ended above its tolerance, within dfsph_error_bound times it
    above_tolerance: int = 0
    window_above_tolerance: int = 0
    # steps tried again with half the dt, because a solve ended beyond dfsph_error_bound times its tolerance
    retries: int = 0
    window_retries: int = 0
    worst_over_tolerance: float = 0.0  # of the window: the largest error / tolerance of those solves
    failure: dict = field(default_factory=dict)  # the solve that ended beyond the bound, if one did

    def summary(self) -> dict:
        n = max(self.window_steps, 1)
        return dict(steps=self.window_steps,
                    density_iterations_mean=self.window_density_iterations / n,
                    density_iterations_max=self.max_density_iterations,
                    divergence_iterations_mean=self.window_divergence_iterations / n,
                    divergence_iterations_max=self.max_divergence_iterations,
                    density_error_max=self.max_density_error, divergence_error_max=self.max_divergence_error,
                    steps_above_tolerance=self.window_above_tolerance, worst_over_tolerance=self.worst_over_tolerance,
                    retries=self.window_retries,
                    round_trips=self.round_trips)


class Stepper:
    """One DFSPH step on a field set: called like a kernel, ``stepper(t_target)``
    (:meth:`taisph.engine.assembly.Solver.step_kernels`), it launches the step's
    kernels and iterates each solve until it converges, reading the mean error (one
    f64) after every iteration. The solve settings are the simulation's controls
    (``fields.controls``, set with the parameters)."""

    def __init__(self, solver, fields, serial_sort: bool):
        self.fields = fields
        step = StepKernels(solver, fields.extra)
        make = solver.make_kernel
        args = fields.args
        self.sort = make(kernels.sort_body(solver, serial_sort))(args)
        self.density = make(step.density())(args)
        self.divergence_iteration = make(step.iteration(density=False))(args)
        self.middle = make(step.middle())(args)
        self.density_iteration = make(step.iteration(density=True))(args)
        # the first with the non-pressure forces (step 3) in the same walk of the pairs
        self.first_density_iteration = make(step.iteration(density=True, first=True))(args)
        self.final = make(step.final())(args)
        self.status, self.result = args.status, fields.extra.result
        self.params, self.dt_max_row = args.params, solver.param_rows["dt_max"]
        self.stats = Stats()  # the simulation's (bind): the stepper is cached with its pooled fields

    def bind(self, stats: Stats | None) -> Stats:
        """Record the solves into `stats` from now on (None: fresh ones) and return them:
        a simulation binds its own when it takes these fields, which are pooled and reused
        by the next simulation of the configuration (:mod:`taisph.engine.fields`)."""
        self.stats = Stats() if stats is None else stats
        return self.stats

    def begin_window(self):
        s = self.stats
        s.window_steps = s.window_density_iterations = s.window_divergence_iterations = 0
        s.max_density_iterations = s.max_divergence_iterations = 0
        s.max_density_error = s.max_divergence_error = 0.0
        s.window_above_tolerance, s.worst_over_tolerance, s.window_retries = 0, 0.0, 0

    def _solve(self, iterate, t_target, tolerance, minimum, maximum, accelerate=False, first=None):
        """Iterate to `tolerance` (`minimum`..`maximum` times); `first`: the first iteration's kernel."""
        result = self.result
        count = 0
        error = 0.0
        cheb = Chebyshev() if accelerate else None  # the weights of the density solve's iterations
        sent = 1.0  # the weight the device holds (result[2]; 1: plain Jacobi)
        while True:
            (first if count == 0 and first is not None else iterate)(t_target)
            count += 1
            error = result[0]
            if count >= minimum and error <= tolerance:
                break
            if count >= maximum:
                break
            if cheb is not None and (weight := cheb.next(error)) != sent:
                result[2] = sent = weight
        if sent != 1.0:
            result[2] = 1.0
        self.stats.round_trips += count
        return count, float(error)

    def _judge(self, what, count, error, tolerance, bound) -> int:
        """0: the solve converged; 1: it ended above `tolerance`, within `bound` times it (kept);
        2: beyond (recorded in ``stats.failure``: the run stops)."""
        if error <= tolerance:
            return 0
        if error <= bound * tolerance:
            self.stats.worst_over_tolerance = max(self.stats.worst_over_tolerance, error / tolerance)
            return 1
        self.stats.failure = dict(solve=what, iterations=count, error=error, tolerance=tolerance, bound=bound,
                                  dt=float(self.status[st.DT]), time=float(self.status[st.TIME]))
        return 2

    def _attempt(self, t_target) -> int:
        """The step up to its last kernel: sort, density, both solves; the worst outcome of
        the solves (:meth:`_judge`). Reads and writes only the sorted copy S (and the
        clock), so that the step can be tried again from C, the state it started from."""
        c = self.fields.controls
        s = self.stats
        self.sort(t_target)
        dt = self.status[st.DT]
        s.round_trips += 1
        if self.status[st.IDLE] > 0.0:  # the clock already stands at the target
            return -1
        self.density(t_target)
        outcome = 0
        initial = self.result[1]  # the divergence error before any iteration
        s.round_trips += 1
        if dt > 0.0 and initial > c.dfsph_divergence_tolerance:
            k, err = self._solve(self.divergence_iteration, t_target, c.dfsph_divergence_tolerance, 1,
                                 c.dfsph_max_iterations)
            outcome = self._judge("divergence", k, err, c.dfsph_divergence_tolerance, c.dfsph_error_bound)
            s.divergence_iterations += k
            s.window_divergence_iterations += k
            s.max_divergence_iterations = max(s.max_divergence_iterations, k)
            if outcome < 2:  # the errors of the solves kept (a failed one is in stats.failure)
                s.max_divergence_error = max(s.max_divergence_error, err)
        self.middle(t_target)
        if dt <= 0.0:  # no solve (the bootstrap): the first iteration's forces, v* and maxima all the same
            self.first_density_iteration(t_target)
        else:
            k, err = self._solve(self.density_iteration, t_target, c.dfsph_tolerance, c.dfsph_min_iterations,
                                 c.dfsph_max_iterations, accelerate=True, first=self.first_density_iteration)
            judged = self._judge("density", k, err, c.dfsph_tolerance, c.dfsph_error_bound)
            outcome = max(outcome, judged)
            s.density_iterations += k
            s.window_density_iterations += k
            s.max_density_iterations = max(s.max_density_iterations, k)
            if judged < 2:
                s.max_density_error = max(s.max_density_error, err)
            s.last_density_error = err
        return outcome

    def _rewind(self, clock, dt):
        """Set the clock back to `clock` (time, steps, dt sum and largest dt before the
        attempt) and cap the next attempt's dt at `dt`."""
        status = self.status
        status[st.TIME], status[st.STEPS], status[st.DT_SUM], status[st.DT_MAX] = clock
        self.params[self.dt_max_row] = dt

    def __call__(self, t_target):
        c = self.fields.controls
        s = self.stats
        status = self.status
        clock = None
        if c.dfsph_retries > 0 and c.dt is None:  # what a retry rewinds to (4 reads: ~30 us of a ~10 ms step)
            clock = (status[st.TIME], status[st.STEPS], status[st.DT_SUM], status[st.DT_MAX])
        outcome = self._attempt(t_target)
        retries = 0
        while outcome == 2 and retries < c.dfsph_retries and c.dt is None and self.fields.args.flags[st.CODES] == 0:
            # the solve ended beyond its bound: the same step again from C with half the dt
            if retries == 0:
                cap = self.params[self.dt_max_row]
            retries += 1
            s.retries += 1
            s.window_retries += 1
            self._rewind(clock, 0.5 * status[st.DT])
            s.failure = {}
            outcome = self._attempt(t_target)
        if retries:
            self.params[self.dt_max_row] = cap
        if outcome < 0:
            return
        if status[st.DT] > 0.0:
            s.steps += 1
            s.window_steps += 1
            if outcome == 1:
                s.above_tolerance += 1
                s.window_above_tolerance += 1
        self.final(t_target)
        if outcome == 2:
            s.failure["retries"] = retries
            flags = self.fields.args.flags
            if status[st.FROZEN] == 0.0:
                flags[st.CODES] = flags[st.CODES] | st.UNCONVERGED
