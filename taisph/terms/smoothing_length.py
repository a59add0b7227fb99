"""Variable smoothing length, h_a = eta (m_a / rho_a)^(1/dim) (Monaghan 2005, Rep. Prog.
Phys. 68:1703, sec. 2; Price 2012, J. Comput. Phys. 231:759, sec. 2).

Each particle's h follows its own volume m/rho, so resolution follows mass: a gas
expanded 8 times has 8 times larger h in 1D. The term stores ``h`` per particle and
sets it from the density every time the equation of state runs (the gather, and again
after a summation-density pass): with :class:`SummationDensity` the density is summed
with the h of the previous density, then h is updated (one fixed-point iteration per
step); with :class:`Continuity` h follows the evolved density directly. No grad-h
(Omega) correction terms are included.

Its presence switches the neighbour sums to per-particle h (compile time, see
:mod:`taisph.engine.kernels`): pair forces use the mean of both particles' kernel gradients,
grad W_ab = [grad W(r_ab, h_a) + grad W(r_ab, h_b)] / 2 (Hernquist & Katz 1989),
which keeps them antisymmetric; density sums use W(r_ab, h_a).

The scene's ``smoothing_length`` is the largest h allowed: the neighbour search
covers the kernel support of that h, and larger values are capped to it. Set it
above the largest h the flow will need (the case files use twice the initial largest).
"""

import numpy as np
import taichi as ti

from ..engine.layout import VARIABLE_H
from ..messages import InputError
from .base import Term


@ti.data_oriented
class AdaptiveSmoothingLength(Term):
    """Parameter: ``h_factor`` (eta, h / (m/rho)^(1/dim); 1.2 - 1.3 for the cubic spline)."""

    name = "adaptive_h"
    params = {"h_factor": 1.2}
    scalars = (VARIABLE_H,)
    derived = (VARIABLE_H,)
    outputs = (VARIABLE_H,)

    def initial(self, scene) -> np.ndarray:
        """h of the scene's particles from their initial mass and density (uncapped)."""
        return self.values["h_factor"] * (scene.mass / scene.density) ** (1.0 / scene.dim)

    def check(self, scene):
        if "xsph" in scene.terms_by_name:
            raise InputError("XSPH assumes a constant smoothing length; it cannot be used with adaptive_h")
        h = self.initial(scene)
        if h.size and h.max() > scene.smoothing_length * (1 + 1e-12):
            raise InputError(
                f"scene {scene.name!r}: the initial smoothing lengths reach {h.max():.4g}, above the scene's "
                f"smoothing_length {scene.smoothing_length:.4g}, the largest h allowed (it sets the "
                "neighbour search range); raise smoothing_length"
            )

    @ti.func
    def derive(self, s: ti.template(), i):
        q = ti.static(self.q)
        volume = s.Ss[q.mass, i] / s.Ss[q.density, i]
        dim = ti.static(self.kernel.dim)
        root = volume
        if ti.static(dim == 2):
            root = ti.sqrt(volume)
        elif ti.static(dim == 3):
            root = ti.pow(volume, 1.0 / 3.0)
        s.Ss[q.h, i] = ti.min(s.params[self.p.h_factor] * root, s.params[self.p_h])
