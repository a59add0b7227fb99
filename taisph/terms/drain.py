"""A drain: fluid that enters a box leaves the simulation (an overflow, a sink, the far end
of a channel that should not fill up), and the mass it took is counted.

After every step, each fluid particle inside the box ``drain_lo <= x <= drain_hi`` is
removed, as the guards remove a particle that left the domain (its kind becomes
``REMOVED``, its position NaN, and ``flags[REMOVED_COUNT]`` counts it), and its mass is
added to the drain's status slot ``mass_drained``, so that

    initial fluid mass = fluid mass + mass_drained

holds to round-off. Walls and the particles another term imposes (an open boundary's
buffer) are left alone. The box is two runtime parameters (``sim.set(drain_lo=...)``
moves it without recompiling).

Written as the worked example of docs/architecture.md, "Adding a subsystem": one launch
of its own after the force pass (``after_force``) and one status slot, declared here and
found by the engine through :mod:`taisph.terms.base`'s protocol.
"""

import numpy as np
import taichi as ti

from ..engine import status as st
from ..engine.kernels import TRACED
from ..engine.layout import FLUID, REMOVED
from ..messages import InputError
from .base import Term


@ti.data_oriented
class Drain(Term):
    """Fluid particles inside the box ``drain_lo`` .. ``drain_hi`` (m) are removed after each step;
    their mass is summed in the status slot ``mass_drained`` (:meth:`mass_drained`)."""

    name = "drain"
    params = {"drain_lo": "vector", "drain_hi": "vector"}
    wall_range = None
    status_slots = {"mass_drained": 1}

    def check(self, scene):
        super().check(scene)
        for key in ("drain_lo", "drain_hi"):
            if key not in self.values:
                raise InputError(f"Drain needs {key} (a corner of the box, {scene.dim} numbers)")
        lo, hi = (np.asarray(self.values[k], float) for k in ("drain_lo", "drain_hi"))
        if lo.shape != (scene.dim,) or hi.shape != (scene.dim,) or not np.all(lo < hi):
            raise InputError(f"Drain: drain_lo must be below drain_hi along every axis, got {lo} and {hi}")

    def after_force(self, solver):
        """The launch after the force pass: every fluid particle in the box removed and its
        mass counted."""
        q, dim, imposed = self.q, solver.dim, solver.imposed_rows
        slot = self.slot.mass_drained

        @ti.func
        def body(s: ti.template(), t_target):
            ti.static(TRACED.add((self.name, "drain")))
            for i in range(s.sizes[st.N_PARTICLES]):
                inside = s.Ci[q.kind, i] == FLUID
                for row in ti.static(imposed):
                    if s.Ci[row, i] != 0:
                        inside = False
                x = s.Cv[q.position, i]
                for d in ti.static(range(dim)):
                    if x[d] < s.params[self.p.drain_lo + d] or x[d] > s.params[self.p.drain_hi + d]:
                        inside = False
                if inside:
                    s.Ci[q.kind, i] = REMOVED
                    s.Cv[q.position, i] = ti.Vector([ti.math.nan] * dim, dt=s.Cv.dtype)
                    s.Cv[q.velocity, i] = ti.Vector.zero(s.Cv.dtype, dim)
                    ti.atomic_add(s.flags[st.REMOVED_COUNT], 1)
                    ti.atomic_add(s.status[slot], ti.cast(s.Cs[q.mass, i], ti.f64))

        return body

    @staticmethod
    def mass_drained(sim) -> float:
        """Mass the drain of simulation `sim` has removed since the start (kg; per metre in 2D)."""
        return float(sim.state.read(sim.solver.status_slot("drain", "mass_drained")))
