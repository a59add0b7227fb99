"""A damping zone (sponge layer): the velocity relaxed towards zero over a strip of the
domain, so that waves running into it die out instead of reflecting (numerical wave
flumes: e.g. the damping zones of DualSPHysics, Altomare et al. 2017, Coastal Eng. 127:37).

Inside the zone, a distance s L past its start along `damping_direction` (L its length,
0 <= s <= 1), every fluid particle feels

    dv/dt += - r s^2 v,

with r = ``damping_rate`` (1/s): zero at the zone's start and growing quadratically, so
that the zone's own start reflects little (the quadratic ramp: Mayer et al. 1998), and
strongest at its end. It removes momentum and energy on purpose: outside the zone
nothing changes. Runtime parameters: ``damping_start`` (a point on the zone's start,
m), ``damping_direction`` (into the zone; its length is L, m), ``damping_rate``.
"""

import numpy as np
import taichi as ti

from ..messages import InputError
from .base import Term


@ti.data_oriented
class DampingZone(Term):
    name = "damping_zone"
    params = {"damping_start": "vector", "damping_direction": "vector", "damping_rate": 10.0}
    wall_range = None

    def check(self, scene):
        super().check(scene)
        for key in ("damping_start", "damping_direction"):
            if key not in self.values:
                raise InputError(f"DampingZone needs {key} (a point and a vector of {scene.dim} numbers)")
        direction = self.values["damping_direction"]
        if not np.linalg.norm(np.asarray(direction, float)) > 0.0:
            raise InputError(f"DampingZone: damping_direction must not be zero, got {direction!r}")
        if not float(self.values["damping_rate"]) >= 0.0:
            raise InputError(f"DampingZone: damping_rate must be >= 0 (1/s), got {self.values['damping_rate']!r}")

    @ti.func
    def particle(self, s: ti.template(), i, rates: ti.template()):
        dim = ti.static(rates.acc.n)
        start = ti.Vector([s.params[self.p.damping_start + d] for d in ti.static(range(dim))])
        direction = ti.Vector([s.params[self.p.damping_direction + d] for d in ti.static(range(dim))])
        along = (s.Sv[self.q.position, i] - start).dot(direction) / direction.norm_sqr()
        if along > 0.0:
            depth = ti.min(along, 1.0)
            rates.acc -= (s.params[self.p.damping_rate] * depth * depth) * s.Sv[self.q.velocity, i]
