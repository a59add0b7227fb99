"""The runtime parameters of a DFSPH solve: the values derived per scene from its
lattice, kernel and terms (:data:`PARAMS`, read by the kernels from the parameter table
like any term's; :mod:`.solver` has the method)."""

import math

from .. import neighbours, smoothing

# Runtime parameters of the solve: values derived per scene (parameter_values), read by
# the kernels from the parameter table like any term's.
PARAMS = (
    ("dfsph_min_neighbours", 1),  # fewer neighbours: no divergence correction (a splash); MIN_NEIGHBOURS
    ("dfsph_relaxation", 1),  # omega of the Jacobi updates: relaxation(scene)
    ("dfsph_rest_ratio", 1),  # the density the density solve aims at, over rho0: lattice_ratio(scene)
    ("dfsph_nu_art", 1),  # artificial viscosity's kinematic viscosity, for dt: artificial_viscosity_nu(scene)
    ("dfsph_divergence_tolerance", 1),  # the control of that name (no divergence velocity when within it)
    ("dfsph_gradient_scale", 1),  # 1 / the lattice's gradient moment, of the pressure force: gradient_scale(scene)
    ("dfsph_pair_q", 1),  # dx / h: pairs closer than dx repel (visitors.PAIRING_REPULSION)
    ("dfsph_pair_w", 1),  # the kernel's shape at dx / h, the repulsion's reference
)
MIN_NEIGHBOURS = {1: 3, 2: 7, 3: 20}  # 2D, 3D: SPlisHSPlasH's


def relaxation(scene) -> float:
    """omega of the Jacobi updates: min(0.5, 2.3 / sqrt(N)), N the lattice particles in
    a kernel support (a ball of it over dx^dim): more neighbours weaken the diagonal the
    update divides by (the bound is the largest that converged in 2D and 3D: docs/dfsph.md,
    "The solve")."""
    ball = neighbours.ball_volume(scene.support_radius, scene.dim)
    return min(0.5, 2.3 / math.sqrt(ball / scene.dx**scene.dim))


def lattice_ratio(scene) -> float:
    """sum_j m_j W_ij / rho0 of a particle inside a cubic lattice of spacing dx (the
    scene's kernel and h): 0.99995 for the cubic spline with h = 1.3 dx in 2D. A solve
    aiming at rho0 itself would read the lattice's density as an expansion and lower
    the pressure of water at rest, step after step."""
    return smoothing.lattice_sum(scene.kernel, scene.dim, scene.smoothing_length, scene.dx)


def parameter_values(scene, controls) -> dict:
    """The values of :data:`PARAMS` for `scene` and the simulation's `controls`."""
    return dict(dfsph_min_neighbours=MIN_NEIGHBOURS[scene.dim], dfsph_relaxation=relaxation(scene),
                dfsph_rest_ratio=lattice_ratio(scene), dfsph_nu_art=artificial_viscosity_nu(scene),
                dfsph_divergence_tolerance=controls.dfsph_divergence_tolerance,
                dfsph_gradient_scale=gradient_scale(scene), dfsph_pair_q=scene.dx / scene.smoothing_length,
                dfsph_pair_w=float(smoothing.make(scene.kernel, scene.dim).f_numpy(scene.dx / scene.smoothing_length)))


def gradient_scale(scene) -> float:
    """1 / B, B the gradient moment of the scene's lattice (:func:`smoothing.lattice_moment`:
    1.0105 for the cubic spline with h = 1.3 dx in 2D): the pressure force's factor. The
    sum sum_j m_j (k_i + k_j) grad_i W_ij overstates a pressure gradient by B on the
    lattice, so water at rest would settle at B times too small a pressure gradient, its
    pressure short at the floor by (1 - 1/B) rho g H (docs/dfsph.md, "Still water").
    Scaling the pressure force (and the factor alpha with it) leaves the velocities the
    solves produce unchanged and gives the pressures their continuum meaning."""
    return 1.0 / smoothing.lattice_moment(scene.kernel, scene.dim, scene.smoothing_length, scene.dx)


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

