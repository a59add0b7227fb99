"""The time step: one formula, used on the device every step and on the host for estimates.

Stability limits (Monaghan 1992 sec. 10; Monaghan 2005 sec. 4.7; Morris, Fox & Zhu
1997 eq. 19 for the viscous one):

    dt_cfl   = C_cfl   h / max_a (c_a + |v_a|)     acoustic + advective (CFL)
    dt_force = C_force sqrt(h / max_a |a_a|)       force (acceleration) condition
    dt_visc  = C_visc  h^2 / nu                    physical viscosity: terms that declare
                                                   a ``viscosity_param`` (laminar viscosity)

Terms add limits of their own (``Term.step_limit``: the capillary limit of surface
tension, the viscous limit of a viscosity per phase), each written once and taken in
:meth:`TimeStep.begin_step`, :func:`initial_dt` and :func:`estimate` alike.

``dt_stable = min(dt_cfl, dt_force, dt_visc)`` is :func:`stable_dt`, the only place
the formula is written: the step kernels call it (as a Taichi function) with the last
rate evaluation's maxima over fluid particles, :func:`initial_dt` with the initial
state (sound speed c0, |g|, nu), and :func:`fixed_dt` for a fixed step chosen before a run.

With a smoothing length per particle (adaptive_h) the device takes each particle's
limits with its own h (:meth:`TimeStep.track`), so the smallest h limits the step, and
:func:`initial_dt` the smallest initial h with the largest signal speed: the device's
first step or less (equal when c + |v| is uniform).

In adaptive mode (the default) ``dt = min(dt_stable, dt_max)``; with a fixed ``dt``
the fixed value is used and the host warns once if it exceeds ``dt_stable``. Either
way the step is shortened so that it ends exactly on the next output time.
"""

import collections
import dataclasses
import inspect
import math
from dataclasses import dataclass

import numpy as np
import taichi as ti

from . import solvers
from . import status as st
from ..scene import parameters
from .layout import VARIABLE_H

TINY = 1e-30  # a limit whose maximum is zero (no flow, no force, no viscosity) imposes none (f32-safe)


@dataclass
class EngineControls:
    """Time-step and guard settings (runtime values: changing one recompiles nothing).

    dt                 fixed time step (s); None: adaptive (the default)
    dt_max             cap on the adaptive step (s)
    courant            C_cfl in dt = C_cfl h / max(c + |v|)             (0.25, or the scene's, or the solver's)
    force_factor       C_force in dt = C_force sqrt(h / max |a|)         (0.25, or the solver's)
    viscous_factor     C_visc in dt = C_visc h^2 / nu                     (0.125)
    max_density_error  stop when |rho/rho0 - 1| exceeds this (0 disables; taisph.engine.guards)
    remove_escaped     remove (and count) particles that leave the domain instead of stopping,
                       and particles whose density leaves the range, up to max_out_of_range;
                       None: as the scene says (``Scene.remove_escaped``)
    max_out_of_range   with remove_escaped: the fraction of the fluid particles that may be
                       removed for their density before the next one stops the run (0.001)
    max_speed          stop when a fluid particle moves faster than this (m/s; 0 disables); None: the
                       solver's default (taisph.engine.guards.max_speed)
    deterministic      serial (stable) cell sort at every size: bit-reproducible runs
    """

    dt: float | None = None
    dt_max: float = math.inf
    courant: float = 0.25
    force_factor: float = 0.25
    viscous_factor: float = 0.125
    max_density_error: float = 0.2
    remove_escaped: bool | None = None
    max_out_of_range: float = 0.001
    max_speed: float | None = None
    deterministic: bool = False


def _composed_controls() -> type:
    """:class:`EngineControls`' fields, then those of each solver's method's controls
    (``Method.Controls``), in the registry's order: one dataclass, :class:`Controls`."""
    specs, docs = [], [inspect.cleandoc(EngineControls.__doc__)]
    for cls in [EngineControls, *(m.Controls for m in solvers.METHODS.values() if m.Controls is not None)]:
        specs += [(f.name, f.type, dataclasses.field(default=f.default)) for f in dataclasses.fields(cls)]
        if cls is not EngineControls:
            docs.append(inspect.cleandoc(cls.__doc__))
    return dataclasses.make_dataclass("Controls", specs, namespace={"__module__": __name__,
                                                                    "__doc__": "\n\n".join(docs)})


Controls = _composed_controls()


# The controls a user sets by name (Simulation(scene, NAME=...), --NAME on the command line with
# _ as -, NAME = ... in a scene file), with their ranges; dt and courant have their own options
SETTABLE = {
    "dt_max": parameters.positive,
    "force_factor": parameters.courant_number,  # (0, 1], as the CFL number
    **{name: rng for m in solvers.METHODS.values() for name, rng in m.ranges.items()},  # the solvers' own
    "max_speed": parameters.Number(0, 1e8),  # m/s; 0: off
}


def controls_for(scene, **given) -> Controls:
    """The controls of a simulation of `scene`: `given` ones, else the defaults of its
    solver's method for the scene (``Method.control_defaults``: the scene's own Courant
    number, ``Scene.courant``, a scene measured to hold a larger one; or the method's),
    else the defaults."""
    for name, value in solvers.of(scene).control_defaults(scene).items():
        if given.get(name) is None and value is not None:
            given[name] = value
    given = {k: v for k, v in given.items() if not (k in ("courant", "force_factor") and v is None)}
    return Controls(**given)


def stable_dt(h, signal, acceleration, viscosity, courant, force_factor, viscous_factor):
    """min(C_cfl h / signal, C_force sqrt(h / acceleration), C_visc h^2 / viscosity).

    `signal` is max(c + |v|), `acceleration` max |a|, `viscosity` the largest
    kinematic viscosity nu; a zero one imposes no limit. Plain Python numbers or, as
    :func:`stable_dt_device`, values inside a Taichi kernel."""
    return ti.min(courant * h / ti.max(signal, TINY),
                  force_factor * ti.sqrt(h / ti.max(acceleration, TINY)),
                  viscous_factor * h * h / ti.max(viscosity, TINY))


stable_dt_device = ti.func(stable_dt)


def kinematic_viscosity(terms) -> float:
    """The largest physical kinematic viscosity nu among `terms` (0 if none)."""
    return max([float(t.values[t.viscosity_param]) for t in terms if t.viscosity_param] + [0.0])


def initial_dt(scene, controls: Controls | None = None, courant: float | None = None) -> float:
    """The stable step of `scene`'s initial state, by :func:`stable_dt`: the signal speed
    is the largest material c0 (or, for an equation of state that computes it, such as
    an ideal gas, the largest initial sound speed) plus the largest initial speed, the
    acceleration |g|, h the smallest initial smoothing length. For a fixed step chosen
    before a run; the adaptive step follows the flow instead."""
    c = controls or controls_for(scene)
    h = scene.smallest_smoothing_length()
    max_sound_speed = getattr(scene.eos, "max_sound_speed", None)
    c_max = max_sound_speed(scene) if max_sound_speed else max(m.c0 for m in scene.materials)
    if not solvers.of(scene).acoustic:
        c_max = 0.0  # incompressible: the step follows the flow speed
    v_max = float(np.max(np.linalg.norm(scene.velocity, axis=1), initial=0.0))
    g = max([float(np.linalg.norm(t.param_values(scene.dim)["gravity"])) for t in scene.terms
             if "gravity" in t.params] + [0.0])
    dt = stable_dt(h, c_max + v_max, g, kinematic_viscosity(scene.terms),
                   c.courant if courant is None else courant, c.force_factor, c.viscous_factor)
    return float(min(dt, c.dt_max, term_limit(scene, c)))


def term_limit(scene, controls: Controls) -> float:
    """The smallest bound the scene's terms put on dt (``Term.step_limit``; inf: none)."""
    return min([t.host_step_limit(scene, controls) for t in scene.terms if t.has_step_limit] + [math.inf])


# A fixed step held for a whole run keeps this margin below the initial stable step:
# the flow's speeds and accelerations lower the limit below its initial estimate (the
# seed scenes' fixed steps from 0.8 x initial_dt pass the check of every step).
FIXED_DT_MARGIN = 0.8


def fixed_dt(scene, controls: Controls | None = None) -> float:
    """A fixed step for a whole run of `scene`: FIXED_DT_MARGIN x :func:`initial_dt`."""
    return FIXED_DT_MARGIN * initial_dt(scene, controls)


PARAMS = (  # runtime parameters, name and width
    ("dt_fixed", 1),  # > 0: fixed time step; 0: adaptive
    ("dt_max", 1),
    ("courant", 1),
    ("force_factor", 1),
    ("viscous_factor", 1),
)


def parameter_values(controls: Controls, dt: float | None = None) -> dict:
    """Values of :data:`PARAMS` for `controls` (`dt`: a one-off fixed step)."""
    fixed = controls.dt if dt is None else dt
    return dict(
        dt_fixed=0.0 if fixed is None else float(fixed),
        dt_max=min(controls.dt_max, 1e30),  # 'no limit', finite in f32 too
        courant=controls.courant,
        force_factor=controls.force_factor,
        viscous_factor=controls.viscous_factor,
    )


@ti.data_oriented
class TimeStep:
    """Inside the step kernels: choose dt and advance the clock (:meth:`begin_step`),
    and collect the maxima the next dt is chosen from (:meth:`track`).

    `viscosity_rows` are the parameter rows of the terms' kinematic viscosities."""

    def __init__(self, param_rows, eos, viscosity_rows=(), limiters=()):
        self.p_h = param_rows["smoothing_length"]
        self.limiters = tuple(limiters)  # bound terms with a step_limit
        self.p = collections.namedtuple("TimeStepRows", [n for n, _ in PARAMS])(*[param_rows[n] for n, _ in PARAMS])
        self.viscosity_rows = tuple(viscosity_rows)
        self.eos = eos
        self.h_row = getattr(eos.q, VARIABLE_H, -1)  # a smoothing length per particle (adaptive_h)?

    @ti.func
    def begin_step(self, s: ti.template(), t_target):
        """(Serial, once per step.) Choose this step's dt and advance the clock."""
        p = ti.static(self.p)
        status = ti.static(s.status)
        # the clock and dt are f64 whatever the state's precision
        nu = ti.cast(0.0, ti.f64)
        for row in ti.static(self.viscosity_rows):
            nu = ti.max(nu, ti.cast(s.params[row], ti.f64))
        dt_stable = stable_dt_device(
            ti.cast(s.params[self.p_h], ti.f64), status[st.MAX_SIGNAL], ti.sqrt(status[st.MAX_ACC2]), nu,
            ti.cast(s.params[p.courant], ti.f64), ti.cast(s.params[p.force_factor], ti.f64),
            ti.cast(s.params[p.viscous_factor], ti.f64))
        for k in ti.static(range(len(self.limiters))):
            dt_stable = ti.min(dt_stable, self.limiters[k].step_limit(s))
        dt = ti.cast(s.params[p.dt_fixed], ti.f64)
        if dt <= 0.0:
            dt = ti.min(dt_stable, ti.cast(s.params[p.dt_max], ti.f64))
        remaining = t_target - status[st.TIME]
        # Idle: the target (an output time, or the end) was reached by an earlier launch of
        # this batch. (The bootstrap, a zero-length step before any step, is not idle: it
        # evaluates the first rates.)
        idle = s.flags[st.CODES] == 0 and remaining <= 0.0 and status[st.STEPS] > 0.0
        status[st.IDLE] = 1.0 if idle else 0.0
        if idle:
            status[st.DT] = 0.0
        else:
            if s.flags[st.CODES] != 0:  # a guard tripped: freeze the state for the diagnosis
                dt = 0.0
                status[st.FROZEN] = 1.0
            elif remaining <= 0.0:  # the bootstrap
                dt = 0.0
            # Only the run's end shortens a step, never an output time (frames, probes,
            # checkpoints): the trajectory does not depend on how often it is looked at
            to_end = status[st.END_TIME] - status[st.TIME]
            if dt > to_end:
                dt = ti.max(to_end, 0.0)
            elif dt < to_end < 1.5 * dt:
                dt = 0.5 * to_end  # two equal steps instead of a sliver before the end
            status[st.DT] = dt
            status[st.DT_STABLE] = dt_stable
            if dt > 0.0:
                status[st.TIME] += dt
                status[st.STEPS] += 1.0
                status[st.DT_SUM] += dt
                status[st.DT_MIN] = ti.min(status[st.DT_MIN], dt)
                status[st.DT_MAX] = ti.max(status[st.DT_MAX], dt)
                status[st.DT_STABLE_MIN] = ti.min(status[st.DT_STABLE_MIN], dt_stable)
            status[st.MAX_ACC2] = 0.0
            status[st.MAX_SIGNAL] = 0.0
            status[st.MAX_DISP2] = 0.0

    @ti.func
    def track(self, s: ti.template(), i, rates: ti.template()):
        """Fold fluid particle i (just updated, in C) into the maxima of |a|^2 and c + |v|.

        With a smoothing length per particle (adaptive_h) each particle's limits take its
        own h_i, the smallest h the tightest: the maxima are kept as seen at the scene's
        h (the one :meth:`begin_step` and :func:`estimate` use), c + |v| scaled by
        h / h_i and |a| likewise, so C h / max(...) = min_i C h_i / (c_i + |v_i|) and
        C sqrt(h / max(...)) = min_i C sqrt(h_i / |a_i|); the viscous limit
        C_visc h_i^2 / nu joins the signal speed as C_cfl h nu / (C_visc h_i^2)."""
        acc2 = ti.cast(rates.acc.norm_sqr(), ti.f64)
        signal = ti.cast(self.eos.sound_speed(s, i) + s.Cv[self.eos.q.velocity, i].norm(), ti.f64)
        if ti.static(self.h_row >= 0):
            h = ti.cast(s.params[self.p_h], ti.f64)
            ratio = h / ti.max(ti.cast(s.Ss[self.h_row, i], ti.f64), TINY)
            acc2 *= ratio * ratio
            signal *= ratio
            if ti.static(len(self.viscosity_rows) > 0):
                nu = ti.cast(0.0, ti.f64)
                for row in ti.static(self.viscosity_rows):
                    nu = ti.max(nu, ti.cast(s.params[row], ti.f64))
                signal = ti.max(signal, ti.cast(s.params[self.p.courant], ti.f64) * nu * ratio * ratio
                                / (ti.cast(s.params[self.p.viscous_factor], ti.f64) * h))
        # Read before the atomic: the maxima rarely grow, and a plain read of a line
        # no thread writes is cheap, while an atomic on it makes both cores fight
        # over the cache line for every particle.
        if acc2 > s.status[st.MAX_ACC2]:
            ti.atomic_max(s.status[st.MAX_ACC2], acc2)
        if signal > s.status[st.MAX_SIGNAL]:
            ti.atomic_max(s.status[st.MAX_SIGNAL], signal)


def estimate(read_status, h: float, controls: Controls, viscosity: float, limit: float = math.inf) -> float:
    """The dt the next adaptive step will take, from the device's maxima (host side);
    `limit` is the terms' own bound (:func:`term_limit`)."""
    dt = stable_dt(h, read_status(st.MAX_SIGNAL), math.sqrt(read_status(st.MAX_ACC2)), viscosity,
                   controls.courant, controls.force_factor, controls.viscous_factor)
    return float(min(dt, controls.dt_max, limit))
