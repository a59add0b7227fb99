"""Density by summation over neighbours (Monaghan 1992 eq. 2.7; Gingold & Monaghan 1977).

    rho_a = sum_b m_b W_ab   (including the particle itself, W_aa = W(0))

An alternative to the continuity equation: density is computed, not evolved, so it
cannot drift; but it is deficient near free surfaces and boundaries, where the kernel
support is not full. By default only fluid neighbours count (``walls=True``
adds wall particles, for wall models whose particles carry a density). Runs as a
neighbour pass before the force pass, then re-evaluates the equation of state.
With a variable smoothing length (:mod:`taisph.terms.smoothing_length`) the sum uses
each particle's own h, rho_a = sum_b m_b W(r_ab, h_a).
"""

import taichi as ti

from ..messages import InputError
from .base import NeighbourPass, Term


@ti.data_oriented
class SummationDensity(Term):
    name = "summation_density"

    takes_walls = True

    def passes(self):
        return [_DensitySum(self)]

    def check(self, scene):
        if any(t.integrates.get("density") for t in scene.terms):
            raise InputError("summation_density and an evolved density (continuity) cannot both be used")
        super().check(scene)


@ti.data_oriented
class _DensitySum(NeighbourPass):
    select = "fluid"
    rederive = True

    def __init__(self, term):
        self.t = term
        self.q = term.q

    @ti.func
    def init(self, s: ti.template(), i):
        return s.Ss[self.q.mass, i] * self.t.w_of(s, 0.0, i)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        if self.t.sees(s, j):
            acc += s.Ss[self.q.mass, j] * w

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        s.Ss[self.q.density, i] = acc
