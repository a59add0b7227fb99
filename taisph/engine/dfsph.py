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

   (walls mirror the pressure of the fluid particle, p_wall = p_i); then v += dt a(kv);
3. the non-pressure forces, the scene's terms that make sense without an equation of
   state (gravity, laminar and artificial viscosity, XSPH; :data:`KEPT`), and the
   hydrostatic head of the walls: a mirrored wall particle b has the pressure
   p_i + rho_i g . (x_b - x_i) (Adami et al. 2012 eq. 27), whose part beyond p_i is
   known, a_i += sum_wall g_ib (g . r_ib) / rho_i. Then v* = v + dt a_nonpressure;
4. the constant-density solve (BK17 algorithm 3): pressures k_i such that the
   predicted density rho*_i + dt^2 sum_j g_ij . (a_i(k) - a_j(k)), with
   rho*_i = rho_i + dt sum_j g_ij . (v*_i - v*_j), is <= rho0;
5. v = v* + dt a(k), x += dt v (symplectic Euler; + dt times the XSPH shift).

Both solves are Jacobi iterations: each iteration computes a(k) for every particle
(one pass over the pairs) and then the residual r_i and the update (another pass),

       k_i <- max(0, k_i + omega r_i / (dt^n D_i)),     n = 1 (divergence), 2 (density),

omega = min(0.5, 2.3 / sqrt(neighbours)) (:func:`relaxation`: 0.5 in 2D, 0.27 in
3D with h = 1.3 dx; a projected Jacobi iteration: pressures may fall, never below zero), r_i
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
unconverged stops the run through the guards (``UNCONVERGED``, :mod:`.diagnosis`).
Each solve starts from the last step's pressures (warm start, BK17 sec. 4.3; the first
from the scene's initial pressure, :func:`initial_kappa`). Particles with fewer than
7 (2D) or 20 (3D) neighbours (splashes) get no divergence correction. The measured
choices behind each of these are in docs/dfsph.md; ``DEFAULTS`` holds the device
parameters that select them.

The time step: dt = min(C h / max|v|, 0.1 sqrt(h / |g|), 0.125 h^2 / nu, dt_max)
(:mod:`.timestep`, the same formula as the weakly compressible step with the signal
speed |v| in place of c + |v|, the body forces as the acceleration, and nu the largest
of the laminar viscosity and the artificial viscosity's alpha h c0 / (2 (d + 2))),
C = 0.3 by default (0.39 dx: BK17's CFL number 0.4 particle diameters; the ``courant``
control).

Walls are particles that carry a volume, m_b / rho0 (their mass as given: the
lattice of the tank's three layers dx apart has the fluid's volume per particle),
in the density sum; the choice and its measurements are in docs/dfsph.md.
"""


import collections
from dataclasses import dataclass, field

import taichi as ti

from . import kernels, pairs
from . import status as st
from .layout import FLUID, WALL

# the terms of a scene that DFSPH keeps (non-pressure forces), and those it replaces
KEPT = ("gravity", "laminar_viscosity", "xsph", "artificial_viscosity")
REPLACED = ("continuity", "summation_density", "pressure", "density_diffusion", "dummy_walls")

CHUNKS = 128  # the error sums: per chunk of particles, then a serial sum (an atomic add costs 5x more)
# device parameters (runtime values, so a measurement can change them without recompiling)
DEFAULTS = dict(
    dfsph_warm_start=1.0,  # fraction of the last step's pressures each solve starts from
    dfsph_wall_mirror=2.0,  # phi: the wall's pressure term is phi k_i (2: p_wall = p_i in the symmetric form)
    dfsph_wall_head=1.0,  # 1: the hydrostatic head of mirrored walls (above); 0: none
    dfsph_min_neighbours=-1.0,  # < 0: 7 in 2D, 20 in 3D (SPlisHSPlasH's), 3 in 1D
    dfsph_relaxation=-1.0,  # omega of the Jacobi update; < 0: relaxation(scene)
    dfsph_increase_only=0.0,  # 1: a solve only raises pressures (SPlisHSPlasH's min(residual, 0))
    dfsph_surface_hold=1.0,  # 1: a particle short of rho0 (free surface) must not be compressed either
    dfsph_rest_ratio=-1.0,
    dfsph_nu_art=-1.0,
    dfsph_divergence_tolerance=-1.0,  # the control of that name (set from the controls)  # the artificial viscosity's kinematic viscosity for the dt limit; < 0: from the scene  # the density the solve aims at over rho0; < 0: the lattice's (lattice_ratio)
)
PARAMS = tuple((name, 1) for name in DEFAULTS)
Extra = collections.namedtuple("Extra", "pairs part result")  # a field set's DFSPH fields (Solver.extra_fields)
MIN_NEIGHBOURS = {1: 3, 2: 7, 3: 20}


def relaxation(scene) -> float:
    """omega of the Jacobi updates: min(0.5, 2.3 / sqrt(N)), N the lattice particles in
    a kernel support (a ball of it over dx^dim). More neighbours weaken the diagonal the
    update divides by. Measured: 2D, h = 1.3 dx (N = 21): 0.5 converges, 0.6 and 0.7
    diverged on the dam break; 3D, h = 1.3 dx (N = 74): 0.5 diverged in the first step,
    0.3 and 0.2 converge (formula: 0.27); 2D, h = 2 dx (N = 50, the probes scene file):
    0.5 diverged, 0.32 (the formula) and 0.25 converge."""
    import math

    support = scene.support_radius
    ball = {1: 2.0 * support, 2: math.pi * support**2, 3: 4.0 / 3.0 * math.pi * support**3}[scene.dim]
    return min(0.5, 2.3 / math.sqrt(ball / scene.dx**scene.dim))


def kept_terms(scene) -> list:
    return [t for t in scene.terms if t.name in KEPT]


def check(scene):
    """Refuse a scene DFSPH cannot run, saying what to change."""
    for t in scene.terms:
        if t.name not in KEPT and t.name not in REPLACED:
            raise ValueError(f"scene {scene.name!r}: the term {t.name!r} cannot be used with solver='dfsph' "
                             f"(DFSPH keeps {', '.join(KEPT)} and replaces {', '.join(REPLACED)} by its pressure "
                             "solve); remove it or use solver='wcsph'")
    if getattr(scene.eos, "name", "") != "tait":
        raise ValueError(f"scene {scene.name!r}: solver='dfsph' simulates incompressible liquids; the scene's "
                         f"equation of state is {scene.eos.name!r}: use solver='wcsph'")
    if scene.neighbour_skin > 0:
        raise ValueError(f"scene {scene.name!r}: solver='dfsph' builds its own pair list every step; set "
                         "neighbour_skin = 0 (--neighbour-skin 0)")


@ti.data_oriented
class Incompressible:
    """What DFSPH has instead of an equation of state: the material table of the Tait
    equation (rho0 for the solve and the guards, c0 for artificial viscosity) and no
    pressure code. The pressure is the solve's, written at the end of every step."""

    name = "incompressible"
    columns = ("rho0", "c0", "gamma", "B")
    scalars = ()
    derived = ()
    outputs = ()

    def material_row(self, material) -> list:
        return [material.rho0, material.c0, material.gamma, material.rho0 * material.c0**2 / material.gamma]

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
    vectors = ["acc_p", "vstar", "gsum"] + (["shift"] if has_shift else []) + (["wall_velocity"] if wall_velocity else [])
    scalars = ["kappa", "kappa_v", "alpha", "source"] + (["wall_weight"] if wall_velocity else [])
    derived = ["acc_p", "vstar", "gsum", "shift", "wall_velocity", "wall_weight", "alpha", "source"]
    return vectors, scalars, derived


def initial_kappa(scene):
    """k = p / rho^2 of the scene's particles at the start, the pressure its Tait
    materials give their initial density (a case that starts in hydrostatic
    equilibrium gives rho0 g depth): the first solve's warm start. Without it the
    first step would have to build the whole pressure field from zero, which takes
    a Jacobi iteration per kernel radius of depth and more (a 0.5 m tank at
    dx = 0.025 did not converge in 100 iterations). Zero for walls and below zero."""
    import numpy as np

    rho0 = np.array([m.rho0 for m in scene.materials])[scene.material]
    c0 = np.array([m.c0 for m in scene.materials])[scene.material]
    gamma = np.array([m.gamma for m in scene.materials])[scene.material]
    p = rho0 * c0**2 / gamma * ((scene.density / rho0) ** gamma - 1.0)
    return np.where(scene.kind == FLUID, np.maximum(p, 0.0) / rho0**2, 0.0)


def lattice_ratio(scene) -> float:
    """sum_j m_j W_ij / rho0 of a particle inside a cubic lattice of spacing dx (the
    scene's kernel and h): 0.99995 for the cubic spline with h = 1.3 dx in 2D. A solve
    aiming at rho0 itself would read the lattice's density as an expansion and lower
    the pressure of water at rest, step after step."""
    import numpy as np

    from . import smoothing

    kernel = smoothing.KERNELS[scene.kernel]
    h, dx, dim = scene.smoothing_length, scene.dx, scene.dim
    reach = int(np.ceil(kernel.support * h / dx))
    axis = np.arange(-reach, reach + 1) * dx
    grid = np.stack(np.meshgrid(*([axis] * dim), indexing="ij"), -1).reshape(-1, dim)
    q = np.linalg.norm(grid, axis=1) / h
    f = {"spline": lambda q: np.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0)),
         "wendland": lambda q: np.where(q < 2, (1 - q / 2) ** 3 * ((1.5 * q + 1) if dim == 1 else
                                                                    (1 - q / 2) * (2 * q + 1)), 0.0),
         "gaussian": lambda q: np.where(q < 3, np.exp(-q * q) - np.exp(-9.0), 0.0)}[scene.kernel]  # smoothing.py
    return float(kernel().sigma(dim) / h**dim * f(q).sum() * dx**dim)


def parameter_values(scene, controls) -> dict:
    values = dict(DEFAULTS)
    if values["dfsph_min_neighbours"] < 0:
        values["dfsph_min_neighbours"] = MIN_NEIGHBOURS[scene.dim]
    if values["dfsph_relaxation"] < 0:
        values["dfsph_relaxation"] = relaxation(scene)
    if values["dfsph_rest_ratio"] < 0:
        values["dfsph_rest_ratio"] = lattice_ratio(scene)
    if values["dfsph_nu_art"] < 0:
        values["dfsph_nu_art"] = artificial_viscosity_nu(scene)
    if values["dfsph_divergence_tolerance"] < 0:
        values["dfsph_divergence_tolerance"] = controls.dfsph_divergence_tolerance
    return values


def artificial_viscosity_nu(scene) -> float:
    """The kinematic viscosity of Monaghan's artificial viscosity, alpha h c0 / (2 (d + 2))
    (Monaghan 2005 sec. 4.6), the largest c0 of the materials; 0 without the term. Its
    explicit step limit 0.125 h^2 / nu joins the time step's (it replaces the force limit
    of the viscous accelerations)."""
    term = scene.terms_by_name.get("artificial_viscosity")
    if term is None:
        return 0.0
    c0 = max(m.c0 for m in scene.materials)
    return float(term.values.get("alpha", 0.1)) * scene.smoothing_length * c0 / (2 * (scene.dim + 2))


# --- the kernel bodies -----------------------------------------------------------------
@ti.data_oriented
class _DensityVisitor:
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
            f = self.kern.f(x)
            acc.rho += mj * s.params[self.p_w_norm] * f
            vi = s.Sv[q.velocity, i]
            acc.div += (vi - s.Sv[q.velocity, j]).dot(g)
            if kind == FLUID:
                acc.gf += g
                acc.g2 += g.dot(g)
            else:
                acc.gb += g
                if ti.static(self.wall_velocity):  # the wall's no-slip velocity: sum_f W v_f, sum_f W
                    ti.atomic_add(s.Ss[q.wall_weight, j], f)
                    ti.atomic_add(s.Sv[q.wall_velocity, j], f * vi)
            self.plist.store(s, i, acc.k, j, coef)
            acc.k += 1


@ti.data_oriented
class _NonPressure:
    """Step 3's visitor of the pair list: the scene's pair terms (as the weakly
    compressible force pass sums them) and the walls' hydrostatic head."""

    def __init__(self, solver):
        self.q = solver.layout.q
        self.terms = [t for t in solver.terms if t.has_pair]
        self.p_gravity = solver.param_rows.get("gravity")
        self.head = self.p_gravity is not None
        self.p_head = solver.param_rows["dfsph_wall_head"]

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, coef, rates: ti.template()):
        """Pair (i, j) of the list, with coef = m_j F(r_ij) (grad_i W_ij = F r_ij): the
        gradient needs no kernel evaluation (it cost the non-pressure pass 30 %)."""
        r = ti.sqrt(r2)
        grad = (coef / s.Ss[self.q.mass, j]) * rij
        for t in ti.static(self.terms):
            ti.static(kernels._traced(t.name, "pair"))
            t.pair(s, i, j, rij, r, grad, rates)
        if ti.static(self.head):
            if s.Si[self.q.kind, j] == WALL and s.params[self.p_head] > 0.0:
                # p_wall - p_i = rho_i g . (x_wall - x_i): a_i -= m_b (that / rho_i^2) grad W
                g = ti.Vector([s.params[self.p_gravity + d] for d in ti.static(range(rij.n))])
                rates.acc += (coef * g.dot(rij) / s.Ss[self.q.density, i]) * rij


class Bodies:
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
        visitor = _DensityVisitor(self.solver, plist)
        kern = self.solver.kernel
        p = self.p
        local = self.local

        wall_velocity = self.wall_velocity
        rho0_col = self.solver.eos.m.rho0

        @ti.func
        def body(s_mem: ti.template(), t_target):
            ti.static(kernels._traced("dfsph", "density"))
            if ti.static(wall_velocity):
                for i in range(s_mem.sizes[4]):
                    if s_mem.Si[q.kind, i] != FLUID:
                        s_mem.Ss[q.wall_weight, i] = 0.0
                        s_mem.Sv[q.wall_velocity, i] = ti.Vector.zero(real, dim)
            for i in range(s_mem.sizes[4]):
                kind = s_mem.Si[q.kind, i]
                if kind == FLUID:
                    s = ti.static(s_mem._replace(params=local(s_mem)))
                    mi = s.Ss[q.mass, i]
                    acc = Acc(rho=mi * s.params[p["w_norm"]] * kern.f(0.0), div=0.0, g2=0.0,
                              gf=ti.Vector.zero(real, dim), gb=ti.Vector.zero(real, dim), k=0)
                    grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p["support2"]], visitor, acc)
                    if not plist.close(s, i, acc.k):
                        _trip(s, q, i, st.CROWDED)
                    s.Ss[q.density, i] = acc.rho
                    phi = s.params[p["dfsph_wall_mirror"]]
                    gsum = acc.gf + phi * acc.gb
                    denominator = gsum.dot(acc.gf + acc.gb) + acc.g2
                    s.Ss[q.alpha, i] = 1.0 / denominator if denominator > 0.0 else 0.0
                    s.Sv[q.gsum, i] = gsum
                    s.Ss[q.source, i] = acc.div
                    if acc.div > 0.0 or s.params[p["dfsph_increase_only"]] == 0.0:
                        s.Ss[q.kappa_v, i] *= s.params[p["dfsph_warm_start"]]
                    else:
                        s.Ss[q.kappa_v, i] = 0.0
                else:  # walls (and removed particles): no pressure, no acceleration, their own velocity
                    s_mem.Ss[q.kappa, i] = 0.0
                    s_mem.Ss[q.kappa_v, i] = 0.0
                    s_mem.Sv[q.acc_p, i] = ti.Vector.zero(real, dim)
                    s_mem.Sv[q.vstar, i] = s_mem.Sv[q.velocity, i]
                    x.pairs.count[i] = 0
            # the divergence error before any iteration (result[1]): within the tolerance, the
            # divergence solve has nothing to do (the host skips it, and ``middle`` with it)
            for c in range(CHUNKS):
                dt = ti.cast(s_mem.status[st.DT], real)
                n = s_mem.sizes[4]
                size = (n + CHUNKS - 1) // CHUNKS
                error = ti.cast(0.0, ti.f64)
                count = 0
                for i in range(c * size, ti.min(c * size + size, n)):
                    if s_mem.Si[q.kind, i] == FLUID:
                        if x.pairs.count[i] >= s_mem.params[p["dfsph_min_neighbours"]]:
                            rho0 = s_mem.mat[s_mem.Si[q.material, i], rho0_col]
                            error += ti.cast(ti.max(s_mem.Ss[q.source, i], 0.0) * dt / rho0, ti.f64)
                        count += 1
                x.part[c, 0] = error
                x.part[c, 1] = ti.cast(count, ti.f64)
            ti.loop_config(serialize=True)
            for _ in range(1):
                total = ti.cast(0.0, ti.f64)
                fluid = ti.cast(0.0, ti.f64)
                for c in range(CHUNKS):
                    total += x.part[c, 0]
                    fluid += x.part[c, 1]
                x.result[1] = total / ti.max(fluid, 1.0)

        return body

    # --- the pressure acceleration and one Jacobi iteration ----------------------------
    def _acceleration(self):
        """ti.func(s, i, row) -> a_i(k) of the pressures in scalar row `row`."""
        q, plist, grid = self.q, self.plist, self.grid
        f = self.x.pairs

        @ti.func
        def acceleration(s: ti.template(), i, row: ti.template()):
            xi = s.Sv[q.position, i]
            a = -s.Ss[row, i] * s.Sv[q.gsum, i]
            for k in range(f.count[i]):
                j = f.nbr[i, k]
                a -= (f.coef[i, k] * s.Ss[row, j]) * grid.separation(s, xi, s.Sv[q.position, j])
            return a

        return acceleration

    def iteration(self, density: bool):
        """One Jacobi iteration of the divergence (density False) or constant-density
        solve: a(k) of every fluid particle, then the residuals, the updates and the
        mean error into ``result[0]``."""
        q, grid, x, real = self.q, self.grid, self.x, self.real
        f = x.pairs
        p = self.p
        local = self.local
        acceleration = self._acceleration()
        row = q.kappa if density else q.kappa_v
        rho0_col = self.solver.eos.m.rho0

        @ti.func
        def body(s_mem: ti.template(), t_target):
            ti.static(kernels._traced("dfsph", "density solve" if density else "divergence solve"))
            for i in range(s_mem.sizes[4]):
                if s_mem.Si[q.kind, i] == FLUID:
                    s_mem.Sv[q.acc_p, i] = acceleration(s_mem, i, row)
            for c in range(CHUNKS):
                s = ti.static(s_mem._replace(params=local(s_mem)))
                dt = ti.cast(s.status[st.DT], real)
                scale = dt * dt if ti.static(density) else dt
                n = s.sizes[4]
                size = (n + CHUNKS - 1) // CHUNKS
                error = ti.cast(0.0, ti.f64)
                count = 0
                for i in range(c * size, ti.min(c * size + size, n)):
                    if s.Si[q.kind, i] == FLUID:
                        xi = s.Sv[q.position, i]
                        ai = s.Sv[q.acc_p, i]
                        change = ti.cast(0.0, real)
                        for k in range(f.count[i]):
                            j = f.nbr[i, k]
                            change += f.coef[i, k] * (ai - s.Sv[q.acc_p, j]).dot(
                                grid.separation(s, xi, s.Sv[q.position, j]))
                        residual = s.Ss[q.source, i] + scale * change
                        rho0 = s.mat[s.Si[q.material, i], rho0_col]
                        if ti.static(not density):
                            if f.count[i] < s.params[p["dfsph_min_neighbours"]]:
                                residual = 0.0  # too few neighbours for a divergence (a splash)
                        # the error: compression, and expansion where the pressure is positive
                        # (there the density must be rho0 both ways; at zero pressure, as at a
                        # free surface, a lower density is allowed)
                        compression = ti.max(residual, 0.0) / rho0
                        if s.Ss[row, i] > 0.0 and s.params[p["dfsph_increase_only"]] == 0.0:
                            compression = ti.abs(residual) / rho0
                        if dt > 0.0:
                            update = residual
                            if s.params[p["dfsph_increase_only"]] > 0.0:
                                update = ti.max(update, 0.0)
                            s.Ss[row, i] = ti.max(0.0, s.Ss[row, i] + s.params[p["dfsph_relaxation"]] * update
                                                  * s.Ss[q.alpha, i] / scale)
                        if ti.static(not density):
                            compression *= dt
                        error += ti.cast(compression, ti.f64)
                        count += 1
                x.part[c, 0] = error
                x.part[c, 1] = ti.cast(count, ti.f64)
            ti.loop_config(serialize=True)
            for _ in range(1):
                total = ti.cast(0.0, ti.f64)
                fluid = ti.cast(0.0, ti.f64)
                for c in range(CHUNKS):
                    total += x.part[c, 0]
                    fluid += x.part[c, 1]
                x.result[0] = total / ti.max(fluid, 1.0)

        return body

    # --- between the solves ---------------------------------------------------------------
    def middle(self):
        """v += dt a(kv) (the divergence solve's result); the walls' no-slip velocity;
        the non-pressure forces and v*; the predicted density rho* (the
        constant-density solve's source) and its warm start."""
        solver = self.solver
        q, grid, plist, x = self.q, self.grid, self.plist, self.x
        f = x.pairs
        dim, real = self.dim, self.real
        p = self.p
        local = self.local
        acceleration = self._acceleration()
        visitor = _NonPressure(solver)
        body_terms = [t for t in solver.terms if t.has_body]
        Rates = solver.Rates
        rho0_col = solver.eos.m.rho0
        wall_velocity, has_shift = self.wall_velocity, self.has_shift

        @ti.func
        def body(s_mem: ti.template(), t_target):
            dt = ti.cast(s_mem.status[st.DT], real)
            skipped = x.result[1] <= s_mem.params[p["dfsph_divergence_tolerance"]]  # no divergence solve
            for i in range(s_mem.sizes[4]):
                if s_mem.Si[q.kind, i] == FLUID:
                    if skipped:
                        s_mem.Ss[q.kappa_v, i] = 0.0
                    else:
                        s_mem.Sv[q.velocity, i] += dt * acceleration(s_mem, i, q.kappa_v)
            if ti.static(wall_velocity):
                # no-slip velocity of the walls (Adami et al. 2012 eq. 22-23), from the sums
                # the fluid scattered in step 1: v_w = 2 v_wall - sum_f v_f W_wf / sum_f W_wf
                for i in range(s_mem.sizes[4]):
                    if s_mem.Si[q.kind, i] == WALL:
                        ghost = s_mem.Sv[q.velocity, i]
                        weight = s_mem.Ss[q.wall_weight, i]
                        if weight > 0.0:
                            ghost = 2.0 * ghost - s_mem.Sv[q.wall_velocity, i] / weight
                        s_mem.Sv[q.wall_velocity, i] = ghost
            for i in range(s_mem.sizes[4]):
                if s_mem.Si[q.kind, i] == FLUID:
                    s = ti.static(s_mem._replace(params=local(s_mem)))
                    rates = Rates(acc=ti.Vector.zero(real, dim))
                    for t in ti.static(body_terms):
                        ti.static(kernels._traced(t.name, "body"))
                        t.body(s, i, rates)
                    # the force limit of dt follows the body forces (gravity): the viscous
                    # terms have their own limit, 0.125 h^2 / nu (timestep.py)
                    acc2 = ti.cast(rates.acc.norm_sqr(), ti.f64)
                    if acc2 > s.status[st.MAX_ACC2]:
                        ti.atomic_max(s.status[st.MAX_ACC2], acc2)
                    xi = s.Sv[q.position, i]
                    plist.for_each(s, i, xi, visitor, rates)
                    s.Sv[q.vstar, i] = s.Sv[q.velocity, i] + dt * rates.acc
                    if ti.static(has_shift):
                        s.Sv[q.shift, i] = rates.shift
            for i in range(s_mem.sizes[4]):
                if s_mem.Si[q.kind, i] == FLUID:
                    s = ti.static(s_mem._replace(params=local(s_mem)))
                    xi = s.Sv[q.position, i]
                    vi = s.Sv[q.vstar, i]
                    change = ti.cast(0.0, real)
                    for k in range(f.count[i]):
                        j = f.nbr[i, k]
                        change += f.coef[i, k] * (vi - s.Sv[q.vstar, j]).dot(grid.separation(s, xi, s.Sv[q.position, j]))
                    # the density error the solve removes: the predicted change and the
                    # compression beyond the rest density (a particle short of rho0, as at a free
                    # surface, keeps its density: it must not be compressed either)
                    rest = s.mat[s.Si[q.material, i], rho0_col] * s.params[p["dfsph_rest_ratio"]]
                    excess = s.Ss[q.density, i] - rest
                    if s.params[p["dfsph_surface_hold"]] > 0.0:
                        excess = ti.max(excess, 0.0)
                    source = excess + dt * change
                    s.Ss[q.source, i] = source
                    # warm start; pressures that only rise (SPlisHSPlasH's rule) start only where
                    # the particle is being compressed: a free surface's would push it out
                    if source > 0.0 or s.params[p["dfsph_increase_only"]] == 0.0:
                        s.Ss[q.kappa, i] *= s.params[p["dfsph_warm_start"]]
                    else:
                        s.Ss[q.kappa, i] = 0.0

        return body

    # --- step 5 ------------------------------------------------------------------------
    def final(self):
        """v = v* + dt a(k), x += dt v; the state back to C; pressure; maxima; guards."""
        solver = self.solver
        layout = solver.layout
        q = self.q
        carried_v, carried_s, carried_i = layout.carried
        dim, real = self.dim, self.real
        integ, guards = solver.integrator, solver.guards
        acceleration = self._acceleration()
        Rates = solver.Rates
        has_shift = self.has_shift
        local = self.local

        @ti.func
        def body(s_mem: ti.template(), t_target):
            dt = ti.cast(s_mem.status[st.DT], real)
            for i in range(s_mem.sizes[4]):
                s = ti.static(s_mem._replace(params=local(s_mem)))
                for k in ti.static(carried_v):
                    s.Cv[k, i] = s.Sv[k, i]
                for k in ti.static(carried_s):
                    s.Cs[k, i] = s.Ss[k, i]
                for k in ti.static(carried_i):
                    s.Ci[k, i] = s.Si[k, i]
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


@ti.func
def _trip(s: ti.template(), q: ti.template(), i, code):
    """Set a guard flag for particle i (as :meth:`taisph.engine.guards.Guards.check`)."""
    if s.status[st.FROZEN] == 0.0:
        ti.atomic_or(s.flags[st.CODES], code)
        k = ti.atomic_add(s.flags[st.COUNT], 1)
        if k < st.MAX_RECORDED:
            s.flags[st.RECORDS + 2 * k] = s.Si[q.id, i]
            s.flags[st.RECORDS + 2 * k + 1] = code


# --- the host side -----------------------------------------------------------------------
@dataclass
class Stats:
    """Iterations and errors of the solves: totals since the simulation started, and
    the window of the current run (:meth:`Stepper.begin_window`)."""

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
    failure: dict = field(default_factory=dict)  # what did not converge, if a solve did not

    def summary(self) -> dict:
        n = max(self.window_steps, 1)
        return dict(steps=self.window_steps,
                    density_iterations_mean=self.window_density_iterations / n,
                    density_iterations_max=self.max_density_iterations,
                    divergence_iterations_mean=self.window_divergence_iterations / n,
                    divergence_iterations_max=self.max_divergence_iterations,
                    density_error_max=self.max_density_error, divergence_error_max=self.max_divergence_error,
                    round_trips=self.round_trips)


class Stepper:
    """One DFSPH step on a field set: called like a kernel, ``stepper(t_target)``
    (:meth:`taisph.engine.assembly.Solver.step_kernels`), it launches the step's
    kernels and iterates each solve until it converges, reading the mean error (one
    f64) after every iteration. The solve settings are the simulation's controls
    (``fields.controls``, set with the parameters)."""

    def __init__(self, solver, fields, serial_sort: bool):
        self.fields = fields
        bodies = Bodies(solver, fields.extra)
        make = solver.make_kernel
        args = fields.args
        self.sort = make(kernels.sort_body(solver, serial_sort))(args)
        self.density = make(bodies.density())(args)
        self.divergence_iteration = make(bodies.iteration(density=False))(args)
        self.middle = make(bodies.middle())(args)
        self.density_iteration = make(bodies.iteration(density=True))(args)
        self.final = make(bodies.final())(args)
        self.status, self.result = args.status, fields.extra.result
        self.stats = Stats()

    def begin_window(self):
        s = self.stats
        s.window_steps = s.window_density_iterations = s.window_divergence_iterations = 0
        s.max_density_iterations = s.max_divergence_iterations = 0
        s.max_density_error = s.max_divergence_error = 0.0

    def _solve(self, iterate, t_target, tolerance, minimum, maximum, what):
        result = self.result
        count = 0
        error = 0.0
        while True:
            iterate(t_target)
            count += 1
            error = result[0]
            if count >= minimum and error <= tolerance:
                break
            if count >= maximum:
                self.stats.failure = dict(solve=what, iterations=count, error=float(error), tolerance=tolerance,
                                          dt=float(self.status[st.DT]), time=float(self.status[st.TIME]))
                break
        self.stats.round_trips += count
        return count, float(error)

    def __call__(self, t_target):
        c = self.fields.controls
        s = self.stats
        self.sort(t_target)
        dt = self.status[st.DT]
        s.round_trips += 1
        self.density(t_target)
        unconverged = False
        initial = self.result[1]  # the divergence error before any iteration
        s.round_trips += 1
        if dt > 0.0 and initial > c.dfsph_divergence_tolerance:
            k, err = self._solve(self.divergence_iteration, t_target, c.dfsph_divergence_tolerance, 1,
                                 c.dfsph_max_iterations, "divergence")
            unconverged = err > c.dfsph_divergence_tolerance
            s.divergence_iterations += k
            s.window_divergence_iterations += k
            s.max_divergence_iterations = max(s.max_divergence_iterations, k)
            s.max_divergence_error = max(s.max_divergence_error, err)
        self.middle(t_target)
        if dt > 0.0:
            k, err = self._solve(self.density_iteration, t_target, c.dfsph_tolerance, c.dfsph_min_iterations,
                                 c.dfsph_max_iterations, "density")
            unconverged = unconverged or err > c.dfsph_tolerance
            s.density_iterations += k
            s.window_density_iterations += k
            s.max_density_iterations = max(s.max_density_iterations, k)
            s.max_density_error = max(s.max_density_error, err)
            s.last_density_error = err
            s.steps += 1
            s.window_steps += 1
        self.final(t_target)
        if unconverged:
            flags = self.fields.args.flags
            if self.status[st.FROZEN] == 0.0:
                flags[st.CODES] = flags[st.CODES] | st.UNCONVERGED
