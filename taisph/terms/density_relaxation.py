"""The evolved density relaxed towards the summed one, where the kernel's support is full.

    d rho_a / dt += (rho_sum,a - rho_a) / tau,      rho_sum,a = sum_b m_b W_ab / kappa

added to the continuity equation's rate (``relaxation_time`` tau, seconds; kappa the
kernel's lattice sum, :func:`taisph.engine.smoothing.lattice_sum`, so that water on the
lattice reads its own density). Applied only to a particle whose support is full,
sum_b (m_b / rho_b) W_ab / kappa >= 0.95: at a free surface or next to a wall the sum
falls short (walls count with ``walls=True``, for dummy walls whose particles carry a
density), and relaxing towards it there would pull the surface in.

Why: an evolved density does not see the particles' spacing. Where particles are packed
tighter or looser than their densities say, nothing pushes them back: the pressure
follows the density, not the packing. Through open boundaries (:mod:`.open_boundary`)
such mismatches come in with the flow and the fluid's particle count walks; relaxing
towards the summed density holds the mass of a reversing stream through an inlet and an
outlet (``tests/test_open_boundaries.py``; the figures with and without the term:
docs/open_boundaries.md, "Validation"). The summed density alone (``SummationDensity``)
restores the count too, but a particle entering from a sparse buffer reads it at once,
light enough to stop the run; here it keeps its evolved density until its support is
full, and is then relaxed over tau.

tau well above the step (the integrator's explicit update is stable for dt < 2 tau) and
below the time over which the count should hold: tens to hundreds of acoustic times
h / c0. Its cost: one neighbour pass before the force pass.
"""

import taichi as ti

from ..engine import smoothing
from ..messages import InputError
from .base import NeighbourPass, Term

FULL_SUPPORT = 0.95  # sum_b V_b W_ab / kappa at or above which a particle's support counts as full


@ti.data_oriented
class DensityRelaxation(Term):
    """Parameters: ``relaxation_time`` (tau, s; required); ``lattice_ratio`` (kappa, set
    from the scene's kernel by :meth:`check`)."""

    name = "density_relaxation"
    params = {"relaxation_time": None, "lattice_ratio": 1.0}
    scalars = ("density_sum",)
    derived = ("density_sum",)
    takes_walls = True

    def passes(self):
        return [_DensitySum(self)]

    def check(self, scene):
        tau = self.values.get("relaxation_time")
        if tau is None or not tau > 0:
            raise InputError(f"density_relaxation needs relaxation_time > 0 (tau, in seconds), got {tau!r}")
        if not any(t.integrates.get("density") for t in scene.terms):
            raise InputError("density_relaxation relaxes an evolved density: the scene needs continuity "
                             "(a summed density, summation_density, has nothing to relax)")
        self.values["lattice_ratio"] = smoothing.lattice_sum(scene.kernel, scene.dim, scene.smoothing_length,
                                                             scene.dx)
        super().check(scene)

    @ti.func
    def particle(self, s: ti.template(), i, rates: ti.template()):
        # density_sum holds the particle's own density where its support is not full (rate 0)
        rates.d[self.r.d_density] += ((s.Ss[self.q.density_sum, i] - s.Ss[self.q.density, i])
                                      / s.params[self.p.relaxation_time])


@ti.data_oriented
class _DensitySum(NeighbourPass):
    select = "fluid"

    def __init__(self, term):
        self.t = term
        self.q = term.q

    @ti.func
    def init(self, s: ti.template(), i):
        w0 = self.t.w_of(s, 0.0, i)
        m = s.Ss[self.q.mass, i]
        return ti.Vector([m * w0, m / s.Ss[self.q.density, i] * w0])

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        if self.t.sees(s, j):
            m = s.Ss[self.q.mass, j]
            acc += ti.Vector([m * w, m / s.Ss[self.q.density, j] * w])

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        kappa = s.params[self.t.p.lattice_ratio]
        rho_sum = s.Ss[self.q.density, i]
        if acc[1] / kappa >= FULL_SUPPORT:
            rho_sum = acc[0] / kappa
        s.Ss[self.q.density_sum, i] = rho_sum
