"""Gravity: a uniform body force, dv_a/dt += g."""

import numpy as np
import taichi as ti

from .base import Term

STANDARD_GRAVITY = 9.81  # m/s^2: every default gravity in taisph and its cases is this one



@ti.data_oriented
class Gravity(Term):
    """Uniform gravitational acceleration ``g`` (a dim-vector, m/s^2).

    Default: :data:`STANDARD_GRAVITY` along -y in 2D and 3D (along -x in 1D).
    """

    name = "gravity"
    params = {"gravity": "vector"}

    def __init__(self, gravity=None):
        super().__init__() if gravity is None else super().__init__(gravity=gravity)
        self._default = None  # the default vector check() filled in, if it did

    @staticmethod
    def default(dim: int) -> tuple:
        """:data:`STANDARD_GRAVITY` along -y (along -x in 1D)."""
        g = [0.0] * dim
        g[min(1, dim - 1)] = -STANDARD_GRAVITY
        return tuple(g)

    def check(self, scene):
        """A Gravity() given no vector takes the default of the scene's dimension, filled
        in here (so ``describe()`` and ``scene.parameters()`` show it), again for a scene of
        another dimension unless it was set since."""
        super().check(scene)
        if not self._given():
            self._default = self.values["gravity"] = self.default(scene.dim)

    def param_values(self, dim):
        """The parameter values for `dim` (pure: reading changes nothing)."""
        if not self._given():
            return {"gravity": np.asarray(self.default(dim), float)}
        return super().param_values(dim)

    def _given(self) -> bool:
        """Was a vector given (or set since), rather than the default filled in?"""
        return "gravity" in self.values and self.values["gravity"] is not getattr(self, "_default", None)

    @ti.func
    def particle(self, s: ti.template(), i, rates: ti.template()):
        for d in ti.static(range(rates.acc.n)):
            rates.acc[d] += s.params[self.p.gravity + d]
