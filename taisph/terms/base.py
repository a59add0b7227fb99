"""What a physical term is, and how the engine plugs it in.

A term is one physical effect: one equation (or one part of one), with its source in
its docstring. The engine assembles its per-step kernels at compile time from the
terms a scene lists, with ``ti.static`` loops, so a term the scene does not list
contributes no code and no memory (:mod:`taisph.engine.kernels`). Its parameters are
runtime values (one slot each in the simulation's parameter array), so changing them
never recompiles a kernel.

A term class declares (all optional):

``name``
    the term's name in descriptions, ``scene.terms_by_name`` and error messages;
``params``
    runtime parameters and their defaults (``float``, ``None`` for "required", or
    ``"vector"`` for a ``dim``-vector such as gravity whose default the term computes);
``vectors``, ``scalars``, ``integers``
    extra per-particle quantities it needs stored (see :mod:`taisph.engine.layout`);
``integrates``
    per-particle scalars it gives a time derivative for, ``{quantity: rate}``;
    the integrator advances them (``density`` from ``d_density`` for continuity);
``takes_walls``
    True if the term accepts ``walls=True``: wall particles then join its neighbour
    sums like fluid ones (for wall models whose particles carry a density, pressure
    and no-slip velocity: dummy walls, :class:`taisph.terms.AdamiWall`, which the
    scene must then list); without it, or with ``walls=False``, the term sums over
    fluid neighbours only. Test a neighbour with :meth:`sees`;
``wall_range``
    for a term that looks at walls in another way: ``"support"`` (walls in its kernel
    sums, the default), ``None`` (it skips walls), or the name of a length parameter
    (a wall force's cut-off). Neighbour lists keep only the walls within the largest
    range the scene's terms need (plus the skin);
``viscosity_param``
    the name of the parameter holding a physical kinematic viscosity nu (m^2/s),
    which limits the time step to C h^2 / nu (:mod:`taisph.engine.timestep`);
``material_columns``
    names of :class:`taisph.scene.Material` attributes the term reads per material
    (e.g. ``("viscosity",)``): the engine appends them to the material table after the
    equation of state's columns, and the term finds them as ``self.m.<name>``
    (``s.mat[material, self.m.viscosity]``); like every material constant they are
    runtime values (``Scene.set``, ``Material.set``);
``derived``
    which of its stored quantities it recomputes every step from the state (in
    ``derive`` or a pass): they are not carried from one step to the next;
``has_shift``
    the term adds ``rates.shift``, a velocity correction that moves particles but is
    not their momentum (XSPH); the integrator advances positions with v + shift;
``outputs``
    quantities written to the ParaView frames besides the standard ones;
``accumulators``
    extra members of the rates accumulator, ``{name: "scalar" | "vector" | "matrix"}``
    (dim, dim x dim), zero at the start of each particle's sum: neighbour sums a term
    gathers in ``pair`` and reads back in ``finish`` (particle shifting's free-surface
    detection); the names are shared by all terms;
``options``
    compile-time options (part of the kernel cache key), set by the constructor.

A term that is a whole subsystem (open boundaries, moving bodies, ...) may also declare:

``imposed_row``
    the name of an integer row (in ``integers``) marking fluid particles whose state the
    term imposes instead of integrating (a nonzero value): they move with their own
    velocity, take no part in the fluid's rates, and are not counted as fluid
    (``Simulation.fluid``, the run's fluid mass);
``creates_particles``
    True if the term adds or retires particles during a step; its :meth:`reserve` says
    how many free slots the host must keep ahead of a batch of steps. A new particle
    takes its id from the engine's ``flags[NEXT_ID]``; one that found no room counts in
    ``flags[NO_ROOM]`` (:mod:`taisph.engine.status`), and the run stops saying so;
``device_arrays``
    ``{name: DeviceArray(dtype, capacity, carried)}``: one-dimensional device arrays of
    its own, seen in kernels as ``s.store.<name>`` (``dtype`` "real" for the state's
    precision or "f64"). :meth:`array_values` gives their values: a ``carried`` array is
    state (written when the particles are uploaded, kept in checkpoints under its name,
    read back by ``State.read_array``), any other is a table of parameters (written with
    the runtime parameters, every time they change);
``status_slots``, ``flag_slots``
    ``{name: count}``: slots of its own in the device's f64 ``status`` and i32 ``flags``
    arrays (sums over a step, counters), allocated per configuration after the engine's
    own; the bound copy finds them as ``self.slot.<name>`` and ``self.flag.<name>``, the
    host as ``Solver.status_slot(term_name, name)``;
``escape_advice``
    what to change when particles pass a wall this term makes (a sentence the diagnosis of a
    failed run gives, :mod:`taisph.engine.diagnosis`), or None;
``runs_after``
    names of other terms whose launches (``after_sort``, ``after_force``) must come
    before this term's at the same stage (e.g. open boundaries re-classify particles
    only after the bodies moved). Otherwise launches run in the scene's order of terms.

and the hooks it needs, ``ti.func`` methods the engine calls if the class defines them:

``pair(s, i, j, rij, r, grad, rates)``
    contribution of neighbour ``j`` to fluid particle ``i`` (``rij = x_i - x_j``,
    ``r = |rij|``, ``grad = grad_i W_ij``), added to the local accumulator ``rates``:
    ``rates.acc`` (dv/dt) and ``rates.d[self.r.<rate>]`` (e.g. ``self.r.d_density``);
``particle(s, i, rates)``
    a contribution that needs no neighbour (gravity);
``step_limit(s)``
    (once per step, serial) a bound on this step's dt, in f64, from the runtime
    parameters and the material table (a capillary or a per-phase viscous limit); the
    engine takes the smallest of these and its own limits. A term that has one also
    defines ``host_step_limit(scene, controls)`` (plain Python), the same bound for the
    initial step and the host's estimates, written with the same formula;
``finish(s, i, rates)``
    called after every pair of particle i is summed, before the integrator reads the
    rates: a term that corrects its own sum by the whole neighbourhood (particle shifting
    at a free surface);
``derive(s, i)``
    run for every particle after the equation of state when the state is gathered in
    cell order: per-particle quantities the pair sums reuse (e.g. P / rho^2), stored
    in the term's own ``scalars``;
``passes()``
    (plain Python) :class:`NeighbourPass` objects: neighbour sums that must be
    complete before the rates are summed (wall pressure from the fluid, summation
    density);
``after_sort(solver)``, ``after_force(solver)``
    (plain Python, at compile time) a ``ti.func`` ``body(s, t_target)`` the engine
    compiles into a launch of its own, right after the sort (before the neighbour
    passes) or right after the force pass; its top-level loops run in parallel
    (``ti.loop_config(serialize=True)`` for a serial one). ``solver`` is the
    :class:`taisph.engine.assembly.Solver` (its ``grid``, ``integrator``, ``param_rows``,
    ``kernel``...);
``reserve(scene)``
    (plain Python) with ``creates_particles``: free particle slots to keep;
``array_values(name)``
    (plain Python) the values of its device array `name` (see ``device_arrays``);
``initial_status()``
    (plain Python) ``{slot name: value}`` of its status slots at the start (default 0);
``check(scene)``
    (plain Python) raise :class:`taisph.messages.InputError` (a ValueError; exit
    code 2 on the command line) if the term cannot work in `scene`, saying what to change.

Inside the hooks ``s`` is the kernel context (:class:`taisph.engine.assembly.Args`:
sorted state ``s.Sv``, ``s.Ss``, ``s.Si``; parameters ``s.params``; material table
``s.mat``); ``self.q.<quantity>``, ``self.p.<param>``, ``self.m.<material constant>``
and ``self.r.<rate>`` are compile-time row indices set by :meth:`Term.bound`.

Adding a term: a checklist is in docs/architecture.md.
"""

import collections
import copy
import math

import numpy as np
import taichi as ti

from ..engine.layout import FLUID, VARIABLE_H
from ..messages import InputError

HOOKS = ("pair", "particle", "derive", "finish", "step_limit")
LAUNCHES = ("after_sort", "after_force")  # hooks returning a launch of the term's own


class DeviceArray(collections.namedtuple("DeviceArray", "dtype capacity carried")):
    """A term's own device array (``Term.device_arrays``): ``dtype`` "real" (the state's
    precision) or "f64", its length, and whether it is state (``carried``: uploaded with
    the particles, kept in checkpoints) or a table of parameters."""

    __slots__ = ()


class Term:
    name = ""
    params: dict = {}
    vectors: tuple = ()
    scalars: tuple = ()
    integers: tuple = ()
    integrates: dict = {}
    derived: tuple = ()
    takes_walls = False
    wall_range = "support"
    viscosity_param = None
    material_columns: tuple = ()
    has_shift = False
    outputs: tuple = ()
    accumulators: dict = {}
    # subsystems (see the module docstring)
    imposed_row = None
    creates_particles = False
    device_arrays: dict = {}
    status_slots: dict = {}
    flag_slots: dict = {}
    runs_after: tuple = ()
    escape_advice = None
    # the hooks; a subclass defines those it needs as ti.func methods
    pair = None
    particle = None
    derive = None
    finish = None
    step_limit = None
    after_sort = None  # (plain Python methods returning a ti.func body)
    after_force = None

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        for hook in HOOKS:  # has_<hook> is derived: a declared one could disagree with the code
            if f"has_{hook}" in cls.__dict__:
                raise TypeError(f"{cls.__name__} sets has_{hook}; remove it: the engine calls {hook}() "
                                "exactly when the class defines it")

    @property
    def has_pair(self) -> bool:
        return type(self).pair is not None

    @property
    def has_particle(self) -> bool:
        return type(self).particle is not None

    @property
    def has_derive(self) -> bool:
        return type(self).derive is not None

    @property
    def has_finish(self) -> bool:
        return type(self).finish is not None

    @property
    def has_step_limit(self) -> bool:
        return type(self).step_limit is not None

    def host_step_limit(self, scene, controls) -> float:
        """The bound :meth:`step_limit` puts on dt, on the host (inf: none)."""
        return math.inf

    def launches(self, stage: str) -> bool:
        """Does the term have a launch of its own at `stage` (one of LAUNCHES)?"""
        return getattr(type(self), stage) is not None

    def __init__(self, walls: bool = False, **values):
        unknown = set(values) - set(self.params)
        if unknown:
            raise TypeError(
                f"{type(self).__name__} has no parameter(s) {', '.join(sorted(unknown))}; "
                f"it has: {', '.join(self.params) or 'none'}"
            )
        self.options = {}
        if self.takes_walls:
            self.options["walls"] = bool(walls)
        elif walls:
            raise TypeError(f"{type(self).__name__} takes fluid neighbours only (no walls option)")
        self.values = {k: v for k, v in self.params.items() if v != "vector"}
        self.values.update(values)

    # --- compile time -------------------------------------------------------
    def compile_key(self):
        return (type(self).__module__, type(self).__qualname__, tuple(sorted(self.options.items())))

    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        """A copy of this term with compile-time row indices attached."""
        t = copy.copy(self)
        t.r = rate_rows
        t.kernel = kernel
        t.p_inv_h = param_rows.get("inv_h")
        t.p_w_norm = param_rows.get("w_norm")
        t.p_h = param_rows.get("smoothing_length")
        t.p_materials = param_rows.get("materials")
        t.h_row = getattr(layout.q, VARIABLE_H, -1)  # per-particle h, if a term varies it
        t.h_varies = t.h_row >= 0
        t.q = layout.q
        names = list(self.params) or ["none"]
        t.p = collections.namedtuple("ParamRows", names)(*[param_rows.get(k, -1) for k in names])
        t.m = material_cols
        t.eos = eos
        return t

    @property
    def with_walls(self) -> bool:
        """Do wall particles join this term's sums (``walls=True``)?"""
        return self.options.get("walls", False)

    @ti.func
    def sees(self, s: ti.template(), j) -> bool:
        """Does neighbour j take part in this term's sums: fluid, or any with walls=True."""
        seen = True
        if ti.static(not self.with_walls):
            seen = s.Si[self.q.kind, j] == FLUID
        return seen

    # --- runtime ------------------------------------------------------------
    def param_values(self, dim: int) -> dict:
        """Numeric value of every parameter (vectors as arrays of length dim)."""
        out = {}
        for k in self.params:
            if k not in self.values:
                raise InputError(f"{type(self).__name__}: parameter {k!r} has no value")
            v = self.values[k]
            arr = np.atleast_1d(np.asarray(v, dtype=float))
            if self.params[k] == "vector":
                if arr.shape != (dim,):
                    raise InputError(f"{type(self).__name__}.{k} must have {dim} components, got {v!r}")
            elif arr.shape != (1,):
                raise InputError(f"{type(self).__name__}.{k} must be a number, got {v!r}")
            if not np.all(np.isfinite(arr)):
                raise InputError(f"{type(self).__name__}.{k} must be finite, got {v!r}")
            out[k] = arr
        return out

    @ti.func
    def w(self, s: ti.template(), r):
        """The kernel value W(r, h), for terms that need it besides the gradient
        (the scene's constant h; see :meth:`w_of` for a variable one)."""
        return s.params[self.p_w_norm] * self.kernel.f(r * s.params[self.p_inv_h])

    @ti.func
    def h_pair(self, s: ti.template(), i, j):
        """Smoothing length of the pair (i, j): the mean of theirs if h varies."""
        h = s.params[self.p_h]
        if ti.static(self.h_varies):
            h = 0.5 * (s.Ss[self.h_row, i] + s.Ss[self.h_row, j])
        return h

    @ti.func
    def w_of(self, s: ti.template(), r, i):
        """W(r, h_i), the kernel with particle i's smoothing length."""
        result = r
        if ti.static(not self.h_varies):
            result = self.w(s, r)
        else:
            result = self.kernel.w_h(r, s.Ss[self.h_row, i])
        return result

    @ti.func
    def material_count(self, s: ti.template()):
        """The scene's number of materials (the material table may have more rows: loop to this)."""
        return ti.cast(s.params[self.p_materials], ti.i32)

    def wall_reach(self):
        """How far the term looks at wall neighbours: ``"support"``, None (not at all)
        or the name of a length parameter (see ``wall_range``)."""
        if not self.has_pair and type(self).passes is Term.passes:
            return None  # no neighbour sums at all
        if self.takes_walls:
            return "support" if self.with_walls else None
        return self.wall_range

    def passes(self) -> list:
        """Neighbour passes this term needs before the force pass (bound copies)."""
        return []

    def reserve(self, scene) -> int:
        """Free particle slots to keep ahead of a batch of steps (``creates_particles``)."""
        return 0

    def array_values(self, name: str) -> np.ndarray:
        """Values of the device array `name` (``device_arrays``)."""
        raise NotImplementedError(f"{type(self).__name__} declares device array {name!r} but gives no values")

    def initial_status(self) -> dict:
        """Start values of its status slots, by name (those not given start at 0)."""
        return {}

    def check(self, scene) -> None:
        """Raise InputError if the term cannot work in `scene`; the base class checks
        that ``walls=True`` has dummy walls to sum over."""
        if self.with_walls and "dummy_walls" not in scene.terms_by_name:
            raise InputError(f"{type(self).__name__}(walls=True) needs the dummy-wall term (AdamiWall) in the "
                             "scene: wall particles must carry a density, pressure and no-slip velocity")

    def describe(self) -> str:
        parts = [f"{k}={_fmt(v)}" for k, v in self.values.items()]
        if self.with_walls:
            parts.append("walls")
        return f"{self.name}({', '.join(parts)})" if parts else self.name


@ti.data_oriented
class VolumeTerm(Term):
    """A term whose sums use each particle's volume V = m / rho (the multiphase forms:
    :class:`PressureHuAdams`, :class:`ContinuityColagrossi`, :class:`PhaseViscosity`,
    :class:`SurfaceTension`). The ``volume`` row is derived once per particle however many
    such terms a scene lists: the engine runs one derive hook once (they share this one)."""

    scalars = ("volume",)
    derived = ("volume",)

    @ti.func
    def derive(self, s: ti.template(), i):
        s.Ss[self.q.volume, i] = s.Ss[self.q.mass, i] / s.Ss[self.q.density, i]


def _fmt(v):
    if isinstance(v, (tuple, list, np.ndarray)):
        return "(" + ", ".join(_fmt(x) for x in v) + ")"
    if isinstance(v, float):
        return f"{v:.4g}" if math.isfinite(v) else str(v)
    return str(v)


class NeighbourPass:
    """A neighbour sum run after the gather and before the force pass.

    ``select``: which particles it loops over ("fluid", "wall" or "all"). For each,
    ``acc = init(s, i)``; ``pair(s, i, j, rij, r, w, grad, acc)`` for every neighbour
    (w = W_ij, grad = grad_i W_ij); ``finish(s, i, acc)`` stores the result in the
    sorted state (``s.Ss``...). With ``rederive`` the equation of state and the terms'
    ``derive`` run again for that particle afterwards (e.g. after setting density).
    Subclasses are ``@ti.data_oriented`` with ``ti.func`` methods; build them in the
    owning term's :meth:`Term.passes`, which runs after binding, so ``self.q``,
    ``self.p``... of the term are available to pass along.
    """

    select = "fluid"
    rederive = False
