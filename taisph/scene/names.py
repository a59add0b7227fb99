"""The names of the numerical choices a scene makes, in one place: the command line,
scene files, the seed's files, case parameters and the engine's registries all take
them from here (the engine checks at import that its registries implement exactly
these, in this order: the order every message lists them in)."""

SOLVERS = ("wcsph", "dfsph")  # weakly compressible; divergence-free SPH (docs/dfsph.md)
INTEGRATORS = ("euler", "eulermid", "eulermom", "pc")  # eulermom: the seed's name for eulermid
KERNELS = ("spline", "gaussian", "wendland")
UP = 1  # the vertical axis, y, in 2D and 3D: gravity points along -UP, tanks open at +UP
