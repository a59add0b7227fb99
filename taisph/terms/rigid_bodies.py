"""Rigid bodies made of wall particles: prescribed motion (wave makers, gates) and
floating bodies, integrated in the step with the fluid.

A body is a named group of dummy-wall particles (:mod:`.adami_wall`) that moves as one:
each particle keeps its offset r0 from the body's reference point in the body's frame
(``body_offset``), and after every step it is placed at

    x = c + R r0,   v = V + omega x (R r0),   a = A + alpha x r + omega x (omega x r),

with c, R (an angle in 2D, a unit quaternion in 3D), V, omega, A and alpha the body's
state. The dummy walls take v into the no-slip velocity and continuity and a into the
wall pressure (Adami, Hu & Adams 2012, eq. 27: the head uses g - a_w).

**Prescribed** bodies follow a table sampled on a uniform time grid (position offset,
angle, their first and second derivatives; :mod:`taisph.scene.bodies` builds it from a
wave maker's analytic motion, a Python function or a CSV table), interpolated linearly at
the step's end time; past its end the body stays at its last pose.

**Floating** bodies obey Newton-Euler with the force and torque of the fluid and of
contacts, and gravity:

    M dV/dt = F + M g,    2D: I domega/dt = T,    3D: dL/dt = T, omega = R I^-1 R^T L.

The fluid's force on a body particle w is gathered from the very pair terms of the force
pass, F_w = - sum_f m_f a_f<-w, with a_f<-w what the terms' ``pair(f, w)`` add to
dv_f/dt (the same arithmetic, in isolation), so that fluid and bodies exchange equal and
opposite momentum. The body advances by the fluid's integrator's rule (Euler, symplectic
Euler, or the predictor-corrector's velocity Verlet: pose first, then dt/2 (A_prev + A)),
so fluid and bodies keep their total momentum to round-off without gravity. A hinged body
turns about its hinge (its reference point), gravity's torque added. Sums over a body's
particles run serially in cell order (reproducible). Contact: :mod:`.rigid_body_forces`.
"""

import numpy as np
import taichi as ti

from ..messages import InputError
from .base import DeviceArray, Term
from .rigid_body_forces import fluid_contact
from .rigid_body_motion import BodyMotion
from .rigid_body_record import BODY, BODY_COLS, CAPACITY, MOTIONS  # noqa: F401 (BODY_COLS: re-exported)

# the record's offsets by their former names (taisph.run.readout reads a body's state by them)
CENTRE, VELOCITY, ORIENTATION, OMEGA = BODY.centre, BODY.velocity, BODY.orientation, BODY.omega
FORCE, TORQUE = BODY.force, BODY.torque
BODY_ROW = "body"  # 0: no body; k + 1: body k


@ti.data_oriented
class RigidBodies(Term):
    """The scene's moving bodies (:class:`taisph.scene.bodies.Body`, :meth:`taisph.Scene.add_body`);
    compiled only into scenes with some. Contact (with the fluid too: ``pair``) takes the runtime
    parameters ``contact_stiffness`` (1/s^2), ``contact_damping`` (ratio), ``contact_distance`` (m)."""

    name = "rigid_bodies"
    # 0: the default the scene gives (check(): (0.3 c0 / h)^2, 1, dx)
    params = {"contact_stiffness": 0.0, "contact_damping": 1.0, "contact_distance": 0.0}
    vectors = ("body_offset", "wall_acceleration", "body_force")
    derived = ("body_force",)
    integers = (BODY_ROW,)
    outputs = (BODY_ROW,)
    # a subsystem (terms/base.py): the bodies' records and motion tables are device state
    device_arrays = {"bodies": DeviceArray("f64", CAPACITY, carried=True)}

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        fluid_contact(s, self.q, self.p, i, j, rij, r, rates)  # (rigid_body_forces)

    def __init__(self, bodies: list, dim: int):
        super().__init__()
        self.bodies, self.dim = bodies, dim
        self.refresh()

    def refresh(self):
        self.options = {"bodies": tuple(b.motion for b in self.bodies),
                        "hinged": tuple(b.hinge is not None for b in self.bodies)}
        return self

    def describe(self) -> str:
        return f"rigid_bodies({', '.join(f'{b.name}: {b.motion}' for b in self.bodies)})"

    def param_values(self, dim: int) -> dict:
        values = super().param_values(dim)
        for key, auto in getattr(self, "_auto", {}).items():
            if values[key][0] == 0.0:
                values[key] = np.array([auto])
        return values

    def check(self, scene):
        c0 = max(m.c0 for m in scene.materials if hasattr(m, "c0")) if scene.materials else 0.0
        self._auto = {"contact_stiffness": (0.3 * c0 / scene.smoothing_length) ** 2, "contact_distance": scene.dx}
        if scene.solver != "wcsph":
            raise InputError("moving and floating bodies work with the WCSPH solver only (solver = \"wcsph\"): "
                             "DFSPH's pressure solve has no moving walls yet (docs/bodies.md)")
        if "dummy_walls" not in scene.terms_by_name:
            raise InputError("bodies are dummy-wall particles: the scene needs the dummy-wall term "
                             "(AdamiWall; walls = \"dummy\" in the cases and scene files)")
        if scene.neighbour_skin > 0:
            raise InputError("bodies move their wall particles every step: use them without neighbour lists "
                             "(neighbour_skin = 0)")
        if "adaptive_h" in scene.terms_by_name:
            raise InputError("bodies need a constant smoothing length (not adaptive_h)")

    # --- host side: the bodies field ---------------------------------------------------
    def array_values(self, name: str) -> np.ndarray:
        """The ``bodies`` array's initial values (``device_arrays``)."""
        return self.field_values(self.dim)

    def field_values(self, dim: int) -> np.ndarray:
        """The initial ``bodies`` field: one record per body (:data:`.rigid_body_record.BODY`),
        then the prescribed tables."""
        blocks = np.zeros((len(self.bodies), BODY.cols))
        tables = []
        offset = len(self.bodies) * BODY.cols
        for k, b in enumerate(self.bodies):
            row = blocks[k]
            row[BODY.span("centre", dim)] = b.centre
            row[BODY.span("velocity", dim)] = b.velocity
            row[BODY.orientation] = 1.0 if dim == 3 else 0.0  # identity quaternion / angle 0
            omega = np.atleast_1d(np.asarray(b.angular_velocity, float))
            if dim == 2:
                row[BODY.omega + 2] = omega[0]
            else:
                row[BODY.span("omega")] = omega
                row[BODY.span("momentum")] = np.asarray(b.inertia) @ omega
            row[BODY.mass], row[BODY.particle_mass] = b.mass, b.mass / len(b.ids)
            row[BODY.motion] = MOTIONS[b.motion]
            row[BODY.span("hinged_mass_centre", dim)] = b.centre_of_mass if b.hinge is not None else 0.0
            inverse = np.linalg.inv(np.atleast_2d(b.inertia))
            row[BODY.span("inv_inertia", inverse.size)] = inverse.ravel()
            row[BODY.span("free_linear")] = [0.0 if a in b.fixed else 1.0 for a in "xyz"]
            row[BODY.span("free_rotation")] = ([0.0 if "rotation" in b.fixed else 1.0] * 3 if dim == 2 else
                                               [0.0 if r in b.fixed or "rotation" in b.fixed else 1.0
                                                for r in ("rx", "ry", "rz")])
            if b.motion == "prescribed":
                table, table_dt = b.table
                row[BODY.table_offset], row[BODY.table_dt], row[BODY.table_length] = offset, table_dt, len(table)
                row[BODY.span("axis")] = b.axis3
                row[BODY.span("pivot", dim)] = b.centre
                tables.append(table.ravel())
                offset += table.size
        if offset > CAPACITY:
            raise InputError(f"bodies: the motion tables need {offset} numbers, more than the {CAPACITY} they "
                             "have room for; give a coarser table or a shorter run (until)")
        return np.concatenate([blocks.ravel(), *tables]) if tables else blocks.ravel()

    # --- compile time ---------------------------------------------------------------
    def bound(self, layout, param_rows, material_cols, eos, rate_rows, kernel=None):
        t = super().bound(layout, param_rows, material_cols, eos, rate_rows, kernel)
        t.p_gravity = param_rows.get("gravity", -1)
        t.acc_prev_row = getattr(layout.q, "acc_prev", -1)
        t.motions = self.options["bodies"]
        t.hinged = self.options["hinged"]
        return t

    def after_force(self, solver):
        """One launch after the force pass: the fluid's and contacts' force on every
        floating body's particles (parallel), each body's motion (serial), then every
        body particle placed on its body (parallel): :class:`.rigid_body_motion.BodyMotion`."""
        from ..engine.kernels import TRACED

        motion = BodyMotion(self, solver)

        @ti.func
        def body(s: ti.template(), t_target):
            ti.static(TRACED.add((self.name, "body motion")))
            motion.step(s)

        return body
