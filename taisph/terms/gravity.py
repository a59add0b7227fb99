"""Gravity: a uniform body force, dv_a/dt += g."""

import taichi as ti

from .base import Term


@ti.data_oriented
class Gravity(Term):
    """Uniform gravitational acceleration ``g`` (a dim-vector, m/s^2).

    Default: 9.81 m/s^2 along -y in 2D and 3D (along -x in 1D).
    """

    name = "gravity"
    params = {"gravity": "vector"}

    def __init__(self, gravity=None):
        super().__init__() if gravity is None else super().__init__(gravity=gravity)

    def param_values(self, dim):
        if "gravity" not in self.values:
            g = [0.0] * dim
            g[min(1, dim - 1)] = -9.81
            self.values["gravity"] = tuple(g)
        return super().param_values(dim)

    @ti.func
    def body(self, s: ti.template(), i, rates: ti.template()):
        for d in ti.static(range(rates.acc.n)):
            rates.acc[d] += s.params[self.p.gravity + d]
