"""Lennard-Jones repulsion from fixed wall particles (seed eq. 13).

    f_a = sum_walls D [ (r0/r)^p1 - (r0/r)^p2 ] r_ab / r     for r < r0, else 0,

an acceleration on fluid particle a from each wall particle b closer than r0.
Monaghan (1994) introduced this boundary force (there with r_ab / r^2 and D of the
order of the squared largest speed); taisph follows the seed's eq. 13, so ``D`` is an
acceleration (m/s^2). p1 = 12, p2 = 6 as the seed says (compile-time options).

``lj_strength`` is D, ``lj_cutoff`` is r0 (typically the wall particle spacing or the
fluid spacing). The force is evaluated with r >= r0/2: a particle that reaches half
the cut-off sees a capped (still strongly repulsive) force instead of an overflow.
"""

import taichi as ti

from ..engine.layout import WALL
from ..messages import InputError
from .base import Term


@ti.data_oriented
class LennardJonesWall(Term):
    name = "lennard_jones_wall"
    escape_advice = "the Lennard-Jones wall force is too weak for the impact speed (raise lj_strength) or dt too large"
    params = {"lj_strength": None, "lj_cutoff": None}
    wall_range = "lj_cutoff"  # walls act only within r0

    def __init__(self, p1: int = 12, p2: int = 6, **values):
        if not (isinstance(p1, int) and isinstance(p2, int) and p1 > p2 > 0):
            raise ValueError(f"Lennard-Jones exponents need integers p1 > p2 > 0, got p1={p1}, p2={p2}")
        super().__init__(**values)
        self.options = {"p1": p1, "p2": p2}

    def check(self, scene):
        support = scene.support_radius
        if self.values.get("lj_cutoff") is None or self.values.get("lj_strength") is None:
            raise InputError("LennardJonesWall needs lj_strength (D) and lj_cutoff (r0)")
        if not 0 < self.values["lj_cutoff"] <= support:
            raise InputError(
                f"lj_cutoff r0 = {self.values['lj_cutoff']} must be positive and within the "
                f"kernel support radius {support} (the neighbour search range)"
            )

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        if s.Si[self.q.kind, j] == WALL:
            r0 = s.params[self.p.lj_cutoff]
            if r < r0:
                ratio = r0 / ti.max(r, 0.5 * r0)
                f = s.params[self.p.lj_strength] * (
                    ratio ** ti.static(self.options["p1"]) - ratio ** ti.static(self.options["p2"])
                )
                rates.acc += f / ti.max(r, 0.5 * r0) * rij
