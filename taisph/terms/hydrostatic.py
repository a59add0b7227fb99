"""The hydrostatic head between two points, on the device: the one home of g . r.

In a fluid at rest under a uniform body force g, dp = rho g . dx, so two particles
r_ij = x_i - x_j apart differ in pressure by rho g . r_ij (and in density by that over
c^2). The terms that take this hydrostatic part out of a difference, or add it across
a wall (density diffusion, the Riemann formulation's diffusion, dummy walls, open
boundaries), sum g . r with :func:`head`.
"""

import taichi as ti


@ti.func
def head(s: ti.template(), gravity_row: ti.template(), rij):
    """g . r_ij = sum_d g_d r_ij,d, with g the scene's ``gravity`` parameter (its first
    component in parameter row `gravity_row`, compile-time) and r_ij any dim-vector,
    summed from 0.0 over d = 0, 1, 2 in order (the order every caller's results keep)."""
    g_r = 0.0
    for d in ti.static(range(rij.n)):
        g_r += s.params[gravity_row + d] * rij[d]
    return g_r
