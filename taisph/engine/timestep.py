"""Time step control and guards, evaluated inside the step kernels.

Time step (Monaghan 1992 sec. 10; Monaghan 2005 sec. 4.7), at the start of every step
from the previous step's maxima over fluid particles:

    dt_cfl   = C_cfl   h / max_a (c_a + |v_a|)        acoustic + advective (CFL)
    dt_force = C_force sqrt(h / max_a |a_a|)          force (acceleration) condition
    dt_visc  = C_visc  h^2 / nu                       viscous, for terms with a physical
                                                      viscosity nu (their ``viscosity``)

``dt_stable = min(...)``. In adaptive mode (the default) ``dt = min(dt_stable, dt_max)``;
with a fixed ``dt`` the fixed value is used and the host warns once if it exceeds
``dt_stable``. Either way the step is shortened so that it ends exactly on the next
output time. Time, step count and the dt history live on the device (``status``), so
stepping needs no host round trip; the host reads them every few steps.

Guards, per fluid particle after its update (cheap: a comparison per quantity, atomics
only when something is wrong): non-finite position, velocity or density; density
deviating from the material's rho0 by more than ``max_density_error`` (a fraction; 0
disables); a position outside the guard box (the domain grown by one kernel support,
periodic axes excepted). A tripped guard sets a bit in ``flags`` and records up to
``MAX_RECORDED`` particles; from then on every step has dt = 0 (the state stays as it
was when the guard tripped, even if the host only looks a few steps later), and the
host stops and explains (:mod:`taisph.diagnosis`).
With ``remove_escaped`` a particle leaving the guard box is instead turned into an
inactive particle (kind ``removed``: no forces, not written), and counted.
"""

import collections

import taichi as ti

from .layout import REMOVED

# status (f64) entries
TIME, DT, MAX_ACC2, MAX_SIGNAL, DT_MIN, DT_MAX, DT_SUM, STEPS, DT_STABLE_MIN, DT_STABLE, FROZEN = range(11)
# neighbour lists (taisph.grid): largest squared displacement from the positions the
# lists were built at, this step's rebuild decision, a host request to rebuild (state
# changed from outside), and the number of rebuilds so far
MAX_DISP2, REBUILD, FORCE_REBUILD, REBUILDS = range(11, 15)
STATUS_SIZE = 16

# flags (i32) entries and failure bits
CODES, COUNT, REMOVED_COUNT = 0, 1, 2
RECORDS = 3  # (id, code) pairs from here
MAX_RECORDED = 16
FLAGS_SIZE = RECORDS + 2 * MAX_RECORDED
NONFINITE, DENSITY, ESCAPED = 1, 2, 4
CODE_NAMES = {NONFINITE: "non-finite state", DENSITY: "density error", ESCAPED: "left the domain"}

PARAMS = (  # name, width ("dim" = one per axis)
    ("dt_fixed", 1),  # > 0: fixed time step; 0: adaptive
    ("dt_max", 1),
    ("courant", 1),
    ("force_factor", 1),
    ("dt_viscous", 1),  # C_visc h^2 / nu_max from the terms (inf if none)
    ("max_density_error", 1),
    ("remove_escaped", 1),
    ("guard_lo", "dim"),
    ("guard_hi", "dim"),
    ("list_skin", 1),  # neighbour list skin (length); the lists hold pairs closer than
    ("list_reach2", 1),  # (support + skin)^2
    ("list_wall_reach2", 1),  # (wall range + skin)^2, if no term needs walls farther
)


@ti.data_oriented
class Stepping:
    def __init__(self, dim, real, layout, param_rows, eos, periodic):
        self.dim = dim
        self.real = real
        self.q = layout.q
        names = ["smoothing_length"] + [name for name, _ in PARAMS]
        self.p = collections.namedtuple("SteppingRows", names)(*[param_rows[n] for n in names])
        self.eos = eos
        self.periodic = tuple(periodic)

    @ti.func
    def begin_step(self, s: ti.template(), t_target):
        """Choose this step's dt (serial, once per step) and advance the clock."""
        p = ti.static(self.p)
        # the clock and dt are f64 whatever the state's precision
        h = ti.cast(s.params[p.smoothing_length], ti.f64)
        big = ti.cast(1e300, ti.f64)
        dt_cfl = big
        if s.status[MAX_SIGNAL] > 0.0:
            dt_cfl = ti.cast(s.params[p.courant], ti.f64) * h / s.status[MAX_SIGNAL]
        dt_force = big
        if s.status[MAX_ACC2] > 0.0:
            dt_force = ti.cast(s.params[p.force_factor], ti.f64) * ti.sqrt(h / ti.sqrt(s.status[MAX_ACC2]))
        dt_stable = ti.min(dt_cfl, dt_force, ti.cast(s.params[p.dt_viscous], ti.f64))
        dt = ti.cast(s.params[p.dt_fixed], ti.f64)
        if dt <= 0.0:
            dt = ti.min(dt_stable, ti.cast(s.params[p.dt_max], ti.f64))
        if s.flags[CODES] != 0:  # a guard tripped: freeze the state for the diagnosis
            dt = 0.0
            s.status[FROZEN] = 1.0
        remaining = t_target - s.status[TIME]
        if dt > remaining:
            dt = ti.max(remaining, 0.0)
        elif dt < remaining < 1.5 * dt:
            dt = 0.5 * remaining  # two equal steps instead of a sliver before the target
        s.status[DT] = dt
        s.status[DT_STABLE] = dt_stable
        if dt > 0.0:
            s.status[TIME] += dt
            s.status[STEPS] += 1.0
            s.status[DT_SUM] += dt
            s.status[DT_MIN] = ti.min(s.status[DT_MIN], dt)
            s.status[DT_MAX] = ti.max(s.status[DT_MAX], dt)
            s.status[DT_STABLE_MIN] = ti.min(s.status[DT_STABLE_MIN], dt_stable)
        s.status[MAX_ACC2] = 0.0
        s.status[MAX_SIGNAL] = 0.0
        s.status[MAX_DISP2] = 0.0

    @ti.func
    def track(self, s: ti.template(), i, rates: ti.template()):
        """Maxima for the next dt and the guards, for fluid particle i just updated."""
        q = ti.static(self.q)
        p = ti.static(self.p)
        x = s.Cv[q.position, i]
        v = s.Cv[q.velocity, i]
        rho = s.Cs[q.density, i]
        acc2 = rates.acc.norm_sqr()
        signal = self.eos.sound_speed(s, i) + v.norm()
        # Read before the atomic: the maxima rarely grow, and a plain read of a line
        # no thread writes is cheap, while an atomic on it makes both cores fight
        # over the cache line for every particle.
        acc2_64, signal_64 = ti.cast(acc2, ti.f64), ti.cast(signal, ti.f64)
        if acc2_64 > s.status[MAX_ACC2]:
            ti.atomic_max(s.status[MAX_ACC2], acc2_64)
        if signal_64 > s.status[MAX_SIGNAL]:
            ti.atomic_max(s.status[MAX_SIGNAL], signal_64)
        code = 0
        check = x.sum() + v.sum() + rho + acc2
        if not (check - check == 0.0):  # NaN or inf anywhere
            code |= NONFINITE
        if ti.static(hasattr(self.eos.m, "rho0")):  # EOS with a reference density
            max_error = s.params[p.max_density_error]
            if max_error > 0.0:
                error = ti.abs(rho / s.mat[s.Si[q.material, i], self.eos.m.rho0] - 1.0)
                if error > max_error:
                    code |= DENSITY
        outside = False
        for d in ti.static(range(self.dim)):
            if ti.static(not self.periodic[d]):
                if x[d] < s.params[p.guard_lo + d] or x[d] > s.params[p.guard_hi + d]:
                    outside = True
        if outside and code == 0 and s.params[p.remove_escaped] > 0.0:
            s.Ci[q.kind, i] = REMOVED
            ti.atomic_add(s.flags[REMOVED_COUNT], 1)
        elif outside:
            code |= ESCAPED
        if code != 0 and s.status[FROZEN] == 0.0:
            ti.atomic_or(s.flags[CODES], code)
            k = ti.atomic_add(s.flags[COUNT], 1)
            if k < MAX_RECORDED:
                s.flags[RECORDS + 2 * k] = s.Si[q.id, i]
                s.flags[RECORDS + 2 * k + 1] = code
