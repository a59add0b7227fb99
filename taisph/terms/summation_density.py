"""Density by summation over neighbours (Monaghan 1992 eq. 2.7; Gingold & Monaghan 1977).

    rho_a = sum_b m_b W_ab / kappa   (including the particle itself, W_aa = W(0))

An alternative to the continuity equation: density is computed, not evolved, so it
cannot drift; but it is deficient near free surfaces and boundaries, where the kernel
support is not full. By default only fluid neighbours count (``walls=True``
adds wall particles, for wall models whose particles carry a density). Runs as a
neighbour pass before the force pass, then re-evaluates the equation of state.
With a variable smoothing length (:mod:`taisph.terms.smoothing_length`) the sum uses
each particle's own h, rho_a = sum_b m_b W(r_ab, h_a).

kappa (``lattice_ratio``) is 1 by default. ``lattice=True`` sets it to the sum of the
scene's kernel over its particle lattice, sum_j W_ij dx^dim
(:func:`taisph.engine.smoothing.lattice_sum`), so that water laid out on the lattice
at density rho (mass rho dx^dim) reads rho, not kappa rho: for Wendland C2 with
h = 1.3 dx in 2D kappa = 1.0105, which a sound speed of 9 m/s would read as a
pressure of 0.85 Pa, several times the pressures of a slow channel flow.

Open boundaries: their buffer particles keep the density their zone imposes; they
count in the fluid's sums.
"""

import taichi as ti

from ..engine import smoothing
from ..messages import InputError
from .base import NeighbourPass, Term


@ti.data_oriented
class SummationDensity(Term):
    """Parameter: ``lattice_ratio`` (kappa, above). Option: ``lattice=True`` computes
    it from the scene's kernel, smoothing length and dx."""

    name = "summation_density"
    params = {"lattice_ratio": 1.0}

    takes_walls = True

    def __init__(self, walls: bool = False, lattice: bool = False, **values):
        super().__init__(walls=walls, **values)
        if lattice:  # an option so that a saved scene keeps it (the kernel is the same either way)
            self.options["lattice"] = True

    def passes(self):
        return [_DensitySum(self)]

    def check(self, scene):
        if any(t.integrates.get("density") for t in scene.terms):
            raise InputError("summation_density and an evolved density (continuity) cannot both be used")
        if self.options.get("lattice"):
            self.values["lattice_ratio"] = smoothing.lattice_sum(scene.kernel, scene.dim, scene.smoothing_length,
                                                                 scene.dx)
        super().check(scene)


@ti.data_oriented
class _DensitySum(NeighbourPass):
    select = "fluid"
    rederive = True

    def __init__(self, term):
        self.t = term
        self.q = term.q
        self.zone_row = getattr(term.q, "open_zone", -1)  # open boundaries' buffers keep their density

    @ti.func
    def init(self, s: ti.template(), i):
        return s.Ss[self.q.mass, i] * self.t.w_of(s, 0.0, i)

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        if self.t.sees(s, j):
            acc += s.Ss[self.q.mass, j] * w

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        buffer = False
        if ti.static(self.zone_row >= 0):
            buffer = s.Si[self.zone_row, i] > 0
        if not buffer:
            s.Ss[self.q.density, i] = acc / s.params[self.t.p.lattice_ratio]
