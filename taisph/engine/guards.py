"""Guards: checks of every fluid particle after its update, inside the force kernel.

Cheap (a comparison per quantity; atomics only when something is wrong):

- a non-finite position, velocity, density or acceleration;
- density deviating from the material's rho0 by more than ``max_density_error`` (a
  fraction; 0 disables; only for equations of state with a reference density);
- a speed above ``max_speed`` (m/s, a control; 0 disables): by default the solver's
  method's limit (:meth:`taisph.engine.method.Method.max_speed`): off for the weakly
  compressible solver, whose density guard sees a blow-up first (its pressure follows
  the density); an incompressible solve keeps the density of a particle it kicks away,
  so a speed is what shows its failure, and its limit is on;
- a position outside the guard box: the scene's domain grown by one kernel support,
  except along periodic axes and beyond the faces the scene leaves open
  (``Scene.open_faces``, e.g. the open top of a tank: water may fly up and fall back).

A tripped guard sets a bit in ``flags`` and records up to ``MAX_RECORDED`` particles;
from then on every step has dt = 0 (the state stays as it was when the guard
tripped, even if the host only looks a few steps later), and the host stops and
explains (:mod:`taisph.engine.diagnosis`). With ``remove_escaped`` (a control, or the
scene's default) a particle leaving the guard box is instead turned into an inactive particle (kind ``removed``: no
forces, not written), and counted.

Out of range: with ``remove_escaped``, a fluid particle whose only failure is its
density error is removed and counted too, as DualSPHysics removes particles whose
density leaves its range (``RhopOutMin``/``RhopOutMax``, 700-1300 kg/m^3 by default),
until ``max_out_of_range`` (a fraction of the fluid particles, a control) have been
removed that way; the next one stops the run. Weakly compressible SPH cannot represent
a few particles in flight (a jet's spray thrown against a wall's top is crushed or
stretched beyond the guard's range: docs/stability.md); a blow-up of the bulk removes
many particles at once and reaches the limit.
"""

import collections

import numpy as np
import taichi as ti

from . import status as st
from .layout import REMOVED

PARAMS = (  # runtime parameters, name and width ("dim": one per axis)
    ("max_density_error", 1),
    ("remove_escaped", 1),
    ("guard_lo", "dim"),
    ("guard_hi", "dim"),
    ("max_out_of_range", 1),  # particles that may be removed for their density (see above)
    ("max_speed2", 1),  # max_speed^2 (0: no speed guard)
)
OPEN = 1e30  # the guard position of an open face: never reached


def removes_escaped(scene, controls) -> bool:
    """Are particles leaving the domain removed (else a guard trips)? The controls
    decide if they say, else the scene."""
    return scene.remove_escaped if controls.remove_escaped is None else bool(controls.remove_escaped)


def max_speed(scene, controls, default: float = 0.0) -> float:
    """The speed guard's limit (m/s; 0: none): the control if given, else `default`, the
    solver's method's (:meth:`taisph.engine.method.Method.max_speed`)."""
    if controls.max_speed is not None:
        return float(controls.max_speed)
    return default


def parameter_values(scene, controls, default_speed: float = 0.0) -> dict:
    """Values of :data:`PARAMS` for `scene` and `controls` (`default_speed`: :func:`max_speed`'s)."""
    lo, hi = scene.domain
    margin = scene.support_radius
    guard_lo, guard_hi = lo - margin, hi + margin
    for face in scene.open_faces:
        axis = "xyz".index(face[1])
        if face[0] == "-":
            guard_lo[axis] = -OPEN
        else:
            guard_hi[axis] = OPEN
    return dict(
        max_density_error=controls.max_density_error,
        remove_escaped=1.0 if removes_escaped(scene, controls) else 0.0,
        guard_lo=guard_lo,
        guard_hi=guard_hi,
        max_out_of_range=np.floor(controls.max_out_of_range * scene.n_fluid),
        max_speed2=min(max_speed(scene, controls, default_speed) ** 2, 1e30),
    )


@ti.func
def trip(s: ti.template(), q: ti.template(), i, code):
    """Record guard failure `code` of sorted particle i (its id and the code, up to
    ``MAX_RECORDED`` particles), unless the state is already frozen for a diagnosis."""
    if s.status[st.FROZEN] == 0.0:
        ti.atomic_or(s.flags[st.CODES], code)
        k = ti.atomic_add(s.flags[st.COUNT], 1)
        if k < st.MAX_RECORDED:
            s.flags[st.RECORDS + 2 * k] = s.Si[q.id, i]
            s.flags[st.RECORDS + 2 * k + 1] = code


@ti.data_oriented
class Guards:
    def __init__(self, dim, layout, param_rows, eos, periodic, compression_only=False):
        self.dim = dim
        self.q = layout.q
        self.p = collections.namedtuple("GuardRows", [n for n, _ in PARAMS])(*[param_rows[n] for n, _ in PARAMS])
        self.eos = eos
        self.periodic = tuple(periodic)
        self.has_rho0 = hasattr(eos.m, "rho0")  # compile time: is there a reference density?
        # only compression counts (a method's summation density short of rho0 at a free surface by design)
        self.compression_only = compression_only

    @ti.func
    def remove(self, s: ti.template(), i):
        """Take fluid particle i (in C) out of the simulation, for good: kind ``removed``
        (no forces, not written, not guarded) and position NaN, which no neighbour
        search ever finds within its range (a removed particle left where it was, or
        moving on, would still push its neighbours with its last pressure and blow the
        flow up: docs/stability.md), and velocity zero."""
        q = ti.static(self.q)
        s.Ci[q.kind, i] = REMOVED
        s.Cv[q.position, i] = ti.Vector([ti.math.nan] * self.dim, dt=s.Cv.dtype)
        s.Cv[q.velocity, i] = ti.Vector.zero(s.Cv.dtype, self.dim)
        ti.atomic_add(s.flags[st.REMOVED_COUNT], 1)

    @ti.func
    def check(self, s: ti.template(), i, rates: ti.template()):
        """Check fluid particle i, just updated (in C)."""
        q = ti.static(self.q)
        p = ti.static(self.p)
        x = s.Cv[q.position, i]
        v = s.Cv[q.velocity, i]
        rho = s.Cs[q.density, i]
        code = 0
        check = x.sum() + v.sum() + rho + rates.acc.norm_sqr()
        if not (check - check == 0.0):  # NaN or inf anywhere
            code |= st.NONFINITE
        limit2 = s.params[p.max_speed2]
        if limit2 > 0.0 and v.norm_sqr() > limit2:
            code |= st.SPEED
        if ti.static(self.has_rho0):
            max_error = s.params[p.max_density_error]
            if max_error > 0.0:
                error = rho / s.mat[s.Si[q.material, i], self.eos.m.rho0] - 1.0
                if ti.static(not self.compression_only):
                    error = ti.abs(error)
                if error > max_error:
                    code |= st.DENSITY
        outside = False
        for d in ti.static(range(self.dim)):
            if ti.static(not self.periodic[d]):
                if x[d] < s.params[p.guard_lo + d] or x[d] > s.params[p.guard_hi + d]:
                    outside = True
        remove = s.params[p.remove_escaped] > 0.0
        # a particle leaving the domain is removed whatever its density (it is gone;
        # its density error may come from the walls it just passed): only a non-finite
        # state stops the run
        if outside and code & st.NONFINITE == 0 and remove:
            self.remove(s, i)
            code = 0
        elif outside:
            code |= st.ESCAPED
        if code == st.DENSITY and remove:  # out of range, up to the limit
            if ti.atomic_add(s.flags[st.OUT_OF_RANGE_COUNT], 1) < s.params[p.max_out_of_range]:
                self.remove(s, i)
                code = 0
            else:  # the limit is reached: this one stops the run (and is not counted)
                ti.atomic_sub(s.flags[st.OUT_OF_RANGE_COUNT], 1)
        if code != 0:
            trip(s, q, i, code)


def trip_from_host(state, code: int, ids) -> None:
    """Record failure `code` of the particles `ids` (ids, at most MAX_RECORDED) as a
    guard in a kernel would: for what the host finds between steps (the clock that
    stood still: ``STALLED``)."""
    flags = state.flags.to_numpy()
    flags[st.CODES] |= code
    for pid in list(ids)[: st.MAX_RECORDED - min(int(flags[st.COUNT]), st.MAX_RECORDED)]:
        k = int(flags[st.COUNT])
        flags[st.RECORDS + 2 * k], flags[st.RECORDS + 2 * k + 1] = int(pid), code
        flags[st.COUNT] += 1
    state.flags.from_numpy(flags)


def recorded(flags: np.ndarray) -> np.ndarray:
    """(id, code) rows of the offending particles recorded in a ``flags`` array."""
    count = min(int(flags[st.COUNT]), st.MAX_RECORDED)
    return flags[st.RECORDS : st.RECORDS + 2 * count].reshape(-1, 2)
