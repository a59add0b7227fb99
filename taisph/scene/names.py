"""The names of the numerical choices a scene makes, in one place: the command line,
scene files, the seed's files, case parameters and the engine's registries all take
them from here (the engine checks at import that its registries implement exactly
these, in this order: the order every message lists them in)."""

SOLVERS = ("wcsph", "dfsph")  # weakly compressible; divergence-free SPH (docs/dfsph.md)
INTEGRATORS = ("euler", "eulermid", "eulermom", "pc")  # eulermom: the seed's name for eulermid
KERNELS = ("spline", "gaussian", "wendland")
# the weakly compressible solver's continuity and pressure terms: Monaghan's symmetric form (with
# artificial viscosity and density diffusion), or a Riemann solver between each pair
# (taisph.terms.riemann), whose own dissipation replaces both (alpha and delta then default to 0):
# the scene files' default for one fluid under WCSPH without Lennard-Jones walls (its wall
# treatment is that of dummy walls), for its smoother and more accurate wall pressure at the
# same front (docs/validation.md, "What sets the wall pressure")
FORMULATIONS = ("symmetric", "riemann")

UP = 1  # the vertical axis, y, in 2D and 3D: gravity points along -UP, tanks open at +UP


def default_formulation(spec) -> str:
    """The formulation a scene file gets when it names none (see FORMULATIONS); `spec` has
    the file's ``solver``, ``multiphase`` and ``wall_model`` (a scene file's SceneSpec)."""
    return "riemann" if spec.solver == "wcsph" and not spec.multiphase and spec.wall_model != "lj" else "symmetric"
