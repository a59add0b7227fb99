"""Open boundaries: inflow and outflow zones through which fluid enters and leaves.

An open boundary is a *face* of the fluid region (a segment in 2D, a rectangle in a
coordinate plane in 3D) with a *buffer zone* behind it: `layers` rows of particles,
``dx`` apart, outside the face, at least a kernel support deep, so that the fluid
next to the face has full support. Buffer particles are fluid particles (every term
sums over them like any fluid neighbour) whose velocity and density are imposed, not
integrated (after Tafuni et al. 2018, CMAME 342:604, and the bidirectional buffers of
SPHinXsys; Zhang et al. 2021):

- *velocity*: prescribed, u(x, t) from the zone's table (a constant, a profile, a
  table of (t, u), or a Python function of position and time, tabulated), or
  extrapolated from the fluid: the normal part of a first-order fit of the fluid's
  velocity around the point x_r = x + (h - (x - a) . n) n, a smoothing length inside
  the face on the particle's line normal to it (a, n: a point of the face and its
  inward normal). One value per line, normal only: every line of the buffer moves as
  one, along the normal, so the buffer keeps its lattice and never drifts into a wall;
  without viscosity, water moving in takes the zone's mean speed (uniform_inflow_speed);
- *pressure*: prescribed p (Pa), or extrapolated the same way (the fluid's pressure
  at x_r: zero normal gradient across the buffer); the density follows by the inverse
  equation of state, rho = rho0 (1 + p / B)^(1/gamma) (Tait).

Every step, after the force pass, each zone's particles are re-classified
(:func:`OpenBoundaries.after_force`, serial, so that created particles get the same
ids in every run):

- a buffer particle that crossed the face into the fluid becomes fluid, and a new
  buffer particle is placed ``depth`` behind it (the zone stays filled, on the lattice);
- a fluid particle that crossed the face out of the fluid becomes a buffer particle;
- a buffer particle beyond the zone's far side (or beside it) is retired: its slot is
  reused (the particle arrays are compacted in the same loop);
- the buffer is kept a lattice's spacing (:mod:`taisph.terms.open_boundary_buffer`): a
  buffer particle with an older one of its zone within dx/2 is retired, and, where the
  density is summed, a hole among the zone's lattice sites gets a new one (water that
  flowed out is no lattice, and would bring its crowded pairs and holes back in when the
  flow turns).

So every zone works in both directions (bidirectional): a pressure outlet where a
vortex brings fluid back feeds that fluid in, and an inlet whose flow reverses
swallows it. The mass that crosses each way is summed on the device (the term's status
slots ``mass_in`` and ``mass_out``): fluid mass = initial + in - out exactly.

The particle count changes during a run: the fields have spare room, which the host
grows ahead of need (:meth:`taisph.engine.state.State.ensure_room`).
"""


import collections

import numpy as np
import taichi as ti

from ..engine import status as st
from ..engine.layout import FLUID
from ..messages import InputError
from .base import DeviceArray, Term
from .open_boundary_buffer import BufferUpkeep
from .open_boundary_models import buffer_type, models
from .open_boundary_values import EXTRAPOLATED, PRESCRIBED, Fit, fitted, table_velocity, uniform_inflow_speed

ZONE_ROW = "open_zone"  # integer row: 0 in the fluid, k + 1 in zone k's buffer
TABLE_CAPACITY = 1 << 18  # reals of every zone's velocity table together
FACE_SAMPLES = {2: 65, 3: 17}  # samples of a profile or function along each face axis
TIME_SAMPLES = 513  # samples of a time table or function over its span
PROFILES = ("uniform", "parabolic")


_ZoneRows = collections.namedtuple("ZoneRows", "origin normal axis1 axis2 length1 length2 depth spacing pressure "
                                                "period table_dt table_shape table_offset")


def _param_names(zone, dim: int) -> dict:
    """The zone's runtime parameters and their kinds ("vector" or a number)."""
    p = zone.name + "_"
    return {p + "origin": "vector", p + "normal": "vector", p + "axis1": "vector", p + "axis2": "vector",
            p + "length1": 1.0, p + "length2": 1.0, p + "depth": 1.0, p + "spacing": 1.0, p + "pressure": 0.0,
            p + "period": 0.0,
            p + "table_dt": 0.0, p + "table_shape": "vector3", p + "table_offset": 0.0}


@ti.data_oriented
class OpenBoundaries(Term):
    """The open boundary zones of a scene (:class:`OpenBoundary`, see the module
    docstring). Made and kept up to date by :meth:`taisph.Scene.add_open_boundary`;
    compiled only into scenes that have zones. Runtime parameters, by zone name:
    ``<name>_pressure`` (a prescribed pressure, Pa) and the zone's geometry.

    Two algorithms are options (:meth:`choose`; compile time), each ``None`` for its default:

    ``uniform_inflow``
        water entering through a zone that extrapolates the velocity takes the zone's
        mean normal speed, one uniform stream (:func:`.open_boundary_values.uniform_inflow_speed`).
        Default: on where the scene has no laminar viscosity (Euler's equations need an
        inflow's profile given; with viscosity the fluid sets its own);
    ``fill_holes``
        a hole among a buffer's lattice sites gets a new particle (:mod:`.open_boundary_buffer`).
        Default: on where the density is summed (a summed density reads a hole at once, as a
        light entrant; an evolved one does not, and there filling fed mass in).

    ``describe()`` and the run's header show what each resolved to and why."""

    name = "open_boundaries"
    integers = (ZONE_ROW,)
    wall_range = None
    outputs = (ZONE_ROW,)
    # a subsystem (terms/base.py): buffer particles are imposed, zones create and retire
    # particles, the velocity tables live on the device, and the zones re-classify particles
    # only after bodies moved
    imposed_row = ZONE_ROW
    creates_particles = True
    device_arrays = {"tables": DeviceArray("real", TABLE_CAPACITY, carried=False)}
    runs_after = ("rigid_bodies",)

    @property
    def status_slots(self) -> dict:
        """Mass that entered the fluid from a zone's buffer and mass that left it into one,
        since the start; without viscosity, each zone's sum of its buffer's normal speeds
        and their count, this step."""
        speeds = 2 * len(self.zones) if self.options.get("uniform_inflow") else 0
        return {"mass_in": 1, "mass_out": 1, **({"zone_speeds": speeds} if speeds else {})}

    def array_values(self, name: str) -> np.ndarray:
        return self.table_values()

    CHOICES = ("uniform_inflow", "fill_holes")

    def __init__(self, zones: list, dim: int, dx: float):
        self.zones, self.dim, self.dx = zones, dim, dx
        self._declare()
        super().__init__()
        self.options = {"zones": tuple((z.velocity_mode, z.pressure_mode) for z in zones)}
        self.choices = dict.fromkeys(self.CHOICES)  # None: the default (see the class docstring)
        self._tables = None

    def choose(self, **choices):
        """Set the options ``uniform_inflow`` and ``fill_holes`` (True, False, or None for
        the default); returns the term. E.g.
        ``scene.terms_by_name["open_boundaries"].choose(uniform_inflow=False)``."""
        unknown = set(choices) - set(self.CHOICES)
        if unknown:
            raise InputError(f"open boundaries: no option {', '.join(sorted(unknown))}; "
                             f"the options are {', '.join(self.CHOICES)}")
        for key, value in choices.items():
            if value not in (None, True, False):
                raise InputError(f"open boundaries: {key} must be true, false or none (the default), got {value!r}")
        self.choices.update(choices)
        return self

    def _resolve(self, scene) -> dict:
        """Each option's value in `scene` and why: ``{name: (value, reason)}``."""
        extrapolated = any(z.velocity_mode == EXTRAPOLATED for z in self.zones)
        viscous = "laminar_viscosity" in scene.terms_by_name
        summed = "summation_density" in scene.terms_by_name
        defaults = {"uniform_inflow": (not viscous and extrapolated,
                                       "default: " + ("no zone extrapolates the velocity" if not extrapolated
                                                      else "laminar viscosity" if viscous else "no viscosity")),
                    "fill_holes": (summed, "default: " + ("summed density" if summed else "evolved density"))}
        return {k: (defaults[k] if self.choices.get(k) is None else (self.choices[k], "chosen"))
                for k in self.CHOICES}

    def _declare(self):
        """The zones' runtime parameters, declared as a term's (``params``)."""
        self.params = {}
        for z in self.zones:
            self.params.update({k: ("vector" if v in ("vector", "vector3") else v)
                                for k, v in _param_names(z, self.dim).items()})

    # --- host side ----------------------------------------------------------------
    def refresh(self):
        """Recompute the parameter values from the zones (after a zone was added or changed)."""
        self._declare()
        self.options = {"zones": tuple((z.velocity_mode, z.pressure_mode) for z in self.zones),
                        **{k: v for k, v in self.options.items() if k in self.CHOICES}}
        self.values = {}
        offset = 0
        self._tables = []
        for z in self.zones:
            origin, axes, lengths = z.frame(self.dim)
            axes = axes + [np.zeros(self.dim)] * (2 - len(axes))
            lengths = lengths + [1.0] * (2 - len(lengths))
            p = z.name + "_"
            values = {p + "origin": origin, p + "normal": np.asarray(z.normal, float), p + "axis1": axes[0],
                      p + "axis2": axes[1], p + "length1": lengths[0], p + "length2": lengths[1],
                      p + "depth": z.layers * self.dx, p + "spacing": self.dx, p + "period": z.period or 0.0,
                      p + "pressure": z.pressure if z.pressure is not None else 0.0}
            table, table_dt = (z.table(self.dim) if z.velocity is not None
                               else (np.zeros((1, 1, 1, self.dim)), 0.0))
            values.update({p + "table_dt": table_dt, p + "table_offset": float(offset),
                           p + "table_shape": np.array(table.shape[:3], float)[: self.dim]
                           if self.dim == 3 else np.array(table.shape[:2], float)})
            self._tables.append(table.ravel())
            offset += table.size
            self.values.update(values)
        if offset > TABLE_CAPACITY:
            raise InputError(f"open boundaries: the velocity tables need {offset} numbers, more than the "
                             f"{TABLE_CAPACITY} they have room for; give shorter tables")
        return self

    def describe(self) -> str:
        resolved = getattr(self, "_resolved", None)
        options = ("; " + ", ".join(f"{k}={'on' if v else 'off'} ({why})" for k, (v, why) in resolved.items())
                   if resolved else "")
        return f"open_boundaries({', '.join(z.name for z in self.zones)}{options})"

    def table_values(self) -> np.ndarray:
        """Every zone's velocity table, one after the other (offsets in the parameters)."""
        if self._tables is None:
            self.refresh()
        return np.concatenate(self._tables) if self._tables else np.zeros(1)

    def param_values(self, dim: int) -> dict:
        if self._tables is None:
            self.refresh()
        out = {}
        for k, v in self.values.items():
            arr = np.atleast_1d(np.asarray(v, float))
            if not np.all(np.isfinite(arr)):
                raise InputError(f"open boundaries: {k} must be finite, got {v!r}")
            out[k] = arr
        return out

    def check(self, scene):
        """The solver's and the other terms' fit; the zones themselves are checked by
        :func:`taisph.scene.open_boundary.check` (from :meth:`taisph.Scene.validate`)."""
        if scene.solver == "dfsph":
            raise InputError("open boundaries work with the WCSPH solver only (solver = \"wcsph\"): DFSPH's "
                             "pressure solve has no prescribed-pressure particles yet (docs/open_boundaries.md)")
        if scene.neighbour_skin > 0:
            raise InputError("open boundaries change the particles every step: use them without neighbour "
                             "lists (neighbour_skin = 0)")
        if "adaptive_h" in scene.terms_by_name:
            raise InputError("open boundaries need a constant smoothing length (not adaptive_h): their buffers "
                             "are laid out on the lattice of the scene's dx")
        if type(scene.eos).__name__ != "Tait":
            raise InputError("open boundaries need the Tait equation of state (their density comes from the "
                             "prescribed or extrapolated pressure by its inverse)")
        self._resolved = self._resolve(scene)  # the options (class docstring), shown by describe()
        self.options.update({k: v for k, (v, _) in self._resolved.items()})

    def reserve(self, scene) -> int:
        """Free particle slots to keep ahead of a batch of steps (up to 128): every
        buffer particle once (twice where holes are filled), and each face's row more
        than 32 times (a row crosses a face at most every few steps: |u| dt is a small
        part of dx)."""
        total = 0
        for z in self.zones:
            _, _, lengths = z.frame(self.dim)
            row = int(np.prod([round(length / self.dx) for length in lengths]))
            total += row * ((2 if self.options.get("fill_holes") else 1) * z.layers + 32)
        return total

    # --- compile time ---------------------------------------------------------------
    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        t.rows = [_ZoneRows(**{k[len(z.name) + 1:]: param_rows[k] for k in _param_names(z, self.dim)})
                  for z in self.zones]
        t.modes = self.options["zones"]
        t.p_support2 = param_rows["support2"]
        t.prev_v = tuple(k for k, name in enumerate(layout.vectors) if name.endswith("_prev"))
        t.prev_s = tuple(k for k, name in enumerate(layout.scalars) if name.endswith("_prev"))
        return t

    @ti.func
    def _distance(self, s: ti.template(), z: ti.template(), x):
        """(signed distance of x from zone z's face, positive into the fluid; is x
        beside the face's extent (outside it along a face axis)?)"""
        r = ti.static(self.rows[z])
        dim = ti.static(self.dim)
        origin = ti.Vector([s.params[r.origin + d] for d in ti.static(range(dim))])
        normal = ti.Vector([s.params[r.normal + d] for d in ti.static(range(dim))])
        rel = x - origin
        beside = False
        for k in ti.static(range(dim - 1)):
            axis = ti.Vector([s.params[(r.axis1, r.axis2)[k] + d] for d in ti.static(range(dim))])
            along = rel.dot(axis)
            if along < 0.0 or along > s.params[(r.length1, r.length2)[k]]:
                beside = True
        return rel.dot(normal), beside

    def after_sort(self, solver):
        """The step's first neighbour sum: every buffer particle's velocity and density
        (prescribed, or extrapolated from the fluid around its mirror image; each zone's
        models in :mod:`.open_boundary_models`), in ``S``, before the wall pass and the
        rates read them."""
        from ..engine.kernels import TRACED, derive_all

        q, grid, eos = self.q, solver.grid, self.eos
        p_h = solver.param_rows["smoothing_length"]
        derive = derive_all(solver)
        visitor = Fit(q, solver.kernel, solver.param_rows["inv_h"], solver.param_rows["w_norm"], self.dim)
        zone_models = models(self, p_h)
        Buffer = buffer_type(self.dim, solver.real)
        n_zones, dim = len(self.zones), self.dim

        @ti.func
        def impose(s: ti.template(), i, z: ti.template(), t):
            """Buffer particle i of zone z: its velocity and pressure by the zone's models,
            its density by the inverse equation of state, then what derives from it."""
            x = s.Sv[q.position, i]
            distance, _ = self._distance(s, z, x)
            normal = ti.Vector([s.params[self.rows[z].normal + d] for d in ti.static(range(dim))])
            # one point for the whole line of buffer particles normal to the face: a
            # smoothing length inside it (each row of the buffer then moves as one)
            mirror = x + (s.params[p_h] - distance) * normal
            acc = ti.Vector.zero(s.Sv.dtype, 2 * (dim + 1) ** 2)  # moments (Fit)
            grid.for_each_neighbour(s, i, mirror, s.params[self.p_support2], visitor, acc)
            p_fluid, v_fluid = s.Ss[q.pressure, i], s.Sv[q.velocity, i]
            if acc[0] > 0.0:
                p_fluid, v_fluid = fitted(acc, dim)
            at = Buffer(i=i, x=x, time=t, normal=normal, distance=distance, fitted=ti.cast(acc[0] > 0.0, ti.i32),
                        p_fluid=p_fluid, v_fluid=v_fluid)
            velocity_model, pressure_model = ti.static(zone_models[z])
            v = velocity_model.velocity(s, at, pressure_model)
            p = pressure_model.pressure(s, at, velocity_model, v)
            s.Ss[q.density, i] = eos.density_at(s, s.Si[q.material, i], p)
            s.Sv[q.velocity, i] = v
            derive(s, i)  # pressure (and P/rho^2...) from the new density

        @ti.func
        def body(s: ti.template(), t_target):
            ti.static(TRACED.add((self.name, "buffer pass")))
            t = s.status[st.TIME]
            n = s.sizes[st.N_PARTICLES]
            if s.status[st.IDLE] > 0.0:
                n = 0
            for i in range(n):
                zone = s.Si[q.open_zone, i]
                if s.Si[q.kind, i] == FLUID and zone > 0:
                    for z in ti.static(range(n_zones)):
                        if zone == z + 1:
                            impose(s, i, z, t)
            if ti.static(self.options.get("uniform_inflow", False)):
                self._uniform_inflow(s, n)

        return body

    @ti.func
    def _uniform_inflow(self, s: ti.template(), n):
        """The zones' mean inflow speeds given to their entering water (summed in order:
        reproducible; :func:`.open_boundary_values.uniform_inflow_speed`)."""
        for z in ti.static(range(len(self.zones))):
            s.status[self.slot.zone_speeds + 2 * z] = 0.0
            s.status[self.slot.zone_speeds + 2 * z + 1] = 0.0
        ti.loop_config(serialize=True)
        for i in range(n):
            uniform_inflow_speed(s, self.q, self.rows, self.modes, self.dim, self.slot.zone_speeds, i, False)
        for i in range(n):
            uniform_inflow_speed(s, self.q, self.rows, self.modes, self.dim, self.slot.zone_speeds, i, True)

    def after_force(self, solver):
        """The zones' bookkeeping after the particles moved (serial; see the module
        docstring): fluid <-> buffer across each face, new buffer particles behind
        those that entered, retired ones dropped and the arrays compacted."""
        from ..engine.kernels import TRACED, _CountPairs, copy_rows

        q, grid = self.q, solver.grid
        copy = copy_rows(solver)
        counter = _CountPairs(q)  # how many particles lie within the radius asked for
        upkeep = BufferUpkeep(self, solver, copy)
        n_zones, dim = len(self.zones), self.dim
        prev_v, prev_s = self.prev_v, self.prev_s
        fill_holes = self.options.get("fill_holes", False)

        @ti.func
        def body(s: ti.template(), t_target):
            ti.static(TRACED.add((self.name, "zone bookkeeping")))
            ti.loop_config(serialize=True)
            for _ in range(1):
                if s.status[st.IDLE] == 0.0:
                    n = s.sizes[st.N_PARTICLES]
                    capacity = s.Cv.shape[1]
                    kept, made = 0, 0
                    template = ti.Vector([-1] * n_zones)  # a kept buffer particle of each zone
                    for i in range(n):
                        keep = True
                        if s.Ci[q.kind, i] == FLUID:
                            x = grid.wrap(s, s.Cv[q.position, i])  # (along a periodic face axis)
                            zone = s.Ci[q.open_zone, i]
                            for z in ti.static(range(n_zones)):
                                distance, beside = self._distance(s, z, x)
                                depth = s.params[self.rows[z].depth]
                                if zone == 0 and distance < 0.0 and distance > -depth and not beside:
                                    zone = z + 1  # left the fluid: a buffer particle of this zone
                                    s.Ci[q.open_zone, i] = zone
                                    s.status[self.slot.mass_out] += s.Cs[q.mass, i]
                                    for k in ti.static(prev_v):  # imposed, not integrated: no rates of its own
                                        s.Cv[k, i] = ti.Vector.zero(s.Cv.dtype, dim)
                                    for k in ti.static(prev_s):
                                        s.Cs[k, i] = 0.0
                                elif zone == z + 1:
                                    if distance >= 0.0 and not beside:  # entered the fluid
                                        s.Ci[q.open_zone, i] = 0
                                        s.status[self.slot.mass_in] += s.Cs[q.mass, i]
                                        slot = n + made
                                        normal = ti.Vector([s.params[self.rows[z].normal + d]
                                                            for d in ti.static(range(dim))])
                                        behind = x - depth * normal
                                        # its successor, depth behind it, unless a particle is already
                                        # within half a spacing there (a buffer refilled by fluid that
                                        # flowed out is not a lattice: spawning blind would crowd it)
                                        spacing = s.params[self.rows[z].spacing]
                                        crowd = 0
                                        grid.for_each_neighbour(s, -1, behind, 0.25 * spacing * spacing, counter,
                                                                crowd)
                                        if crowd == 0:
                                            made += upkeep.place(s, i, slot, capacity, behind, zone)
                                    elif distance <= -depth or beside:  # past the far side: retired
                                        keep = False
                                    elif upkeep.crowded(s, zone, x, s.Ci[q.id, i]):
                                        keep = False  # thinned (open_boundary_buffer)
                        if keep:
                            if kept != i:
                                copy(s.C, i, s.C, kept)
                            if ti.static(fill_holes):
                                for z in ti.static(range(n_zones)):
                                    if s.Ci[q.open_zone, kept] == z + 1:
                                        template[z] = kept
                            kept += 1
                    for k in range(made):  # the new ones, after the kept ones
                        if kept != n:
                            copy(s.C, n + k, s.C, kept + k)
                    if ti.static(fill_holes):  # the buffers' holes filled (open_boundary_buffer)
                        for z in ti.static(range(n_zones)):
                            if template[z] >= 0:
                                made += upkeep.fill(s, z, template[z], kept + made, capacity)
                    s.sizes[st.N_PARTICLES] = kept + made

        return body
