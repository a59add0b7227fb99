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

from ..engine import status as st
from ..engine.layout import WALL
from ..messages import InputError
from .base import Term
from .rigid_body_forces import BodyForce, cross2, fluid_contact, perp, rotate_q, turned

# one block of BODY_COLS numbers per body in the ``bodies`` field (f64), then the tables
CENTRE, VELOCITY, ORIENTATION, OMEGA, MOMENTUM = 0, 3, 6, 10, 13
ACC_PREV, ALPHA_PREV, ACC, ALPHA = 16, 19, 22, 25
MASS, PARTICLE_MASS, INV_INERTIA = 28, 29, 30  # 30..38: body-frame inverse inertia (2D: 30 only)
FREE_LINEAR, FREE_ROTATION = 39, 42  # 1 free, 0 fixed, per world axis (2D rotation: 42)
TABLE_OFFSET, TABLE_DT, TABLE_LENGTH, AXIS = 45, 46, 47, 48  # prescribed: its table; 3D rotation axis
FORCE, TORQUE = 51, 54  # the last step's fluid + contact force and torque (for probes)
PIVOT, MOTION, HINGED_MASS_CENTRE = 57, 60, 61  # prescribed pose's reference; motion; hinged: r_c (61..63)
BODY_COLS = 64
CAPACITY = 1 << 18
MOTIONS = {"prescribed": 1, "floating": 2}
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
    def field_values(self, dim: int) -> np.ndarray:
        """The initial ``bodies`` field: one block per body, then the prescribed tables."""
        blocks = np.zeros((len(self.bodies), BODY_COLS))
        tables = []
        offset = len(self.bodies) * BODY_COLS
        for k, b in enumerate(self.bodies):
            row = blocks[k]
            row[CENTRE:CENTRE + dim] = b.centre
            row[VELOCITY:VELOCITY + dim] = b.velocity
            row[ORIENTATION] = 1.0 if dim == 3 else 0.0  # identity quaternion / angle 0
            omega = np.atleast_1d(np.asarray(b.angular_velocity, float))
            if dim == 2:
                row[OMEGA + 2] = omega[0]
            else:
                row[OMEGA:OMEGA + 3] = omega
                row[MOMENTUM:MOMENTUM + 3] = np.asarray(b.inertia) @ omega
            row[MASS], row[PARTICLE_MASS] = b.mass, b.mass / len(b.ids)
            row[MOTION] = MOTIONS[b.motion]
            row[HINGED_MASS_CENTRE:HINGED_MASS_CENTRE + dim] = b.centre_of_mass if b.hinge is not None else 0.0
            inverse = np.linalg.inv(np.atleast_2d(b.inertia))
            row[INV_INERTIA:INV_INERTIA + inverse.size] = inverse.ravel()
            row[FREE_LINEAR:FREE_LINEAR + 3] = [0.0 if a in b.fixed else 1.0 for a in "xyz"]
            row[FREE_ROTATION:FREE_ROTATION + 3] = ([0.0 if "rotation" in b.fixed else 1.0] * 3 if dim == 2 else
                                                    [0.0 if r in b.fixed or "rotation" in b.fixed else 1.0
                                                     for r in ("rx", "ry", "rz")])
            if b.motion == "prescribed":
                table, table_dt = b.table
                row[TABLE_OFFSET], row[TABLE_DT], row[TABLE_LENGTH] = offset, table_dt, len(table)
                row[AXIS:AXIS + 3] = b.axis3
                row[PIVOT:PIVOT + dim] = b.centre
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
        body particle placed on its body (parallel)."""
        from ..engine.kernels import TRACED

        q, grid, dim, real = self.q, solver.grid, self.dim, solver.real
        motions, n_bodies, hinged = self.motions, len(self.motions), self.hinged
        integrator = solver.integrator.name
        gatherer = BodyForce(solver, BODY_COLS, PARTICLE_MASS, MOTION, MOTIONS["floating"])
        p_support2 = solver.param_rows["support2"]
        p_gravity, acc_prev = self.p_gravity, self.acc_prev_row
        n_table = 3 * (dim + 1)  # offset (dim), angle; their rates; their accelerations

        @ti.func
        def vec(s: ti.template(), at, n: ti.template()):
            return ti.Vector([s.bodies[at + d] for d in ti.static(range(n))], dt=ti.f64)

        @ti.func
        def put(s: ti.template(), at, v):
            for d in ti.static(range(v.n)):
                s.bodies[at + d] = v[d]

        @ti.func
        def arm(s: ti.template(), base, r0):
            """R r0 of the body at block `base`."""
            r = r0
            if ti.static(dim == 2):
                a = s.bodies[base + ORIENTATION]
                c, sn = ti.cos(a), ti.sin(a)
                r = ti.Vector([c * r0[0] - sn * r0[1], sn * r0[0] + c * r0[1]], dt=ti.f64)
            else:
                r = rotate_q(vec(s, base + ORIENTATION, 4), r0)
            return r

        @ti.func
        def prescribed(s: ti.template(), base, t):
            """Pose, rates and accelerations of a prescribed body at time t from its table."""
            offset = ti.cast(s.bodies[base + TABLE_OFFSET], ti.i32)
            length = ti.cast(s.bodies[base + TABLE_LENGTH], ti.i32)
            x = t / s.bodies[base + TABLE_DT]
            k = ti.min(ti.max(ti.cast(ti.floor(x), ti.i32), 0), length - 2)  # the last interval ends the table
            frac = ti.min(ti.max(x - k, 0.0), 1.0)
            settled = x > length - 1  # (at its last time exactly: still its last row's rates)
            row = ti.Vector.zero(ti.f64, n_table)
            for c in ti.static(range(n_table)):
                a = s.bodies[offset + k * n_table + c]
                b = s.bodies[offset + (k + 1) * n_table + c]
                row[c] = a + frac * (b - a)
            if settled:  # past the table's end: at rest at its last pose
                for c in ti.static(range(n_table // 3, n_table)):
                    row[c] = 0.0
            return row

        @ti.func
        def place(s: ti.template(), i):
            b = s.Ci[q.body, i] - 1
            base = b * BODY_COLS
            r = arm(s, base, ti.cast(s.Cv[q.body_offset, i], ti.f64))
            x = vec(s, base + CENTRE, dim) + r
            v = vec(s, base + VELOCITY, dim)
            a = vec(s, base + ACC, dim)
            if ti.static(dim == 2):
                w, alpha = s.bodies[base + OMEGA + 2], s.bodies[base + ALPHA + 2]
                v += perp(w, r)
                a += perp(alpha, r) - w * w * r
            else:
                w, alpha = vec(s, base + OMEGA, 3), vec(s, base + ALPHA, 3)
                v += w.cross(r)
                a += alpha.cross(r) + w.cross(w.cross(r))
            s.Cv[q.position, i] = ti.cast(x, real)
            s.Cv[q.velocity, i] = ti.cast(v, real)
            s.Cv[q.wall_acceleration, i] = ti.cast(a, real)
            if ti.static(acc_prev >= 0):  # the predictor then moves it along its curve
                s.Cv[acc_prev, i] = ti.cast(a, real)

        @ti.func
        def advance(s: ti.template(), base, dt, force, torque):
            """Newton-Euler for one floating body over dt, by the fluid integrator's rule."""
            g = ti.Vector.zero(ti.f64, dim)
            if ti.static(p_gravity >= 0):
                g = ti.Vector([ti.cast(s.params[p_gravity + d], ti.f64) for d in ti.static(range(dim))])
            free = vec(s, base + FREE_LINEAR, dim)
            acc = (force / s.bodies[base + MASS] + g) * free
            v0 = vec(s, base + VELOCITY, dim)
            a0 = vec(s, base + ACC_PREV, dim)
            v1 = v0 + dt * acc
            dx = dt * v0
            if ti.static(integrator == "eulermid"):
                dx = dt * v1
            elif ti.static(integrator == "pc"):
                v1 = v0 + 0.5 * dt * (a0 + acc)
                dx = dt * v0 + 0.5 * dt * dt * a0
            put(s, base + CENTRE, vec(s, base + CENTRE, dim) + dx)
            put(s, base + VELOCITY, v1)
            put(s, base + ACC_PREV, acc)
            put(s, base + ACC, acc)
            if ti.static(dim == 2):
                free_r = s.bodies[base + FREE_ROTATION]
                alpha = torque[2] * s.bodies[base + INV_INERTIA] * free_r
                w0, al0 = s.bodies[base + OMEGA + 2], s.bodies[base + ALPHA_PREV + 2]
                w1 = w0 + dt * alpha
                da = dt * w0
                if ti.static(integrator == "eulermid"):
                    da = dt * w1
                elif ti.static(integrator == "pc"):
                    w1 = w0 + 0.5 * dt * (al0 + alpha)
                    da = 0.0  # predicted before the torque was summed (predict_pose)
                s.bodies[base + ORIENTATION] += da
                s.bodies[base + OMEGA + 2] = w1
                s.bodies[base + ALPHA_PREV + 2] = alpha
                s.bodies[base + ALPHA + 2] = alpha
            else:
                free_r = vec(s, base + FREE_ROTATION, 3)
                t0 = vec(s, base + ALPHA_PREV, 3)  # 3D: the last step's torque
                L = vec(s, base + MOMENTUM, 3)
                L1 = L + dt * torque
                if ti.static(integrator == "pc"):
                    L1 = L + 0.5 * dt * (t0 + torque)
                quat = vec(s, base + ORIENTATION, 4)
                w0 = vec(s, base + OMEGA, 3)
                if ti.static(integrator != "pc"):  # (pc: predicted before the torque was summed)
                    w_mid = w0
                    if ti.static(integrator == "eulermid"):
                        w_mid = world_omega(s, base, quat, L1) * free_r
                    quat = turned(quat, w_mid, dt)
                w1 = world_omega(s, base, quat, L1) * free_r
                if free_r.min() < 0.5:  # a constrained axis holds no momentum along it
                    L1 = world_inertia(s, base, quat, w1)
                put(s, base + ORIENTATION, quat)
                put(s, base + MOMENTUM, L1)
                put(s, base + OMEGA, w1)
                put(s, base + ALPHA_PREV, torque)
                if dt > 0.0:  # (the zero-length bootstrap step keeps it: w1 - w0 is round-off there)
                    put(s, base + ALPHA, (w1 - w0) / dt)

        @ti.func
        def predict_pose(s: ti.template(), base, dt):
            """pc: the orientation at the step's end, where its particles were predicted,
            set before the torque's sum takes its lever arms (docs/bodies.md)."""
            if ti.static(dim == 2):
                s.bodies[base + ORIENTATION] += dt * s.bodies[base + OMEGA + 2] \
                    + 0.5 * dt * dt * s.bodies[base + ALPHA_PREV + 2]
            else:
                rate = vec(s, base + OMEGA, 3) + 0.5 * dt * vec(s, base + ALPHA, 3)  # the step's mean
                put(s, base + ORIENTATION, turned(vec(s, base + ORIENTATION, 4), rate, dt))

        @ti.func
        def gravity_torque(s: ti.template(), base):
            """(R r_c) x M g of a hinged body, r_c its centre of mass from the hinge."""
            torque = ti.Vector.zero(ti.f64, 3)
            if ti.static(p_gravity >= 0):
                g = ti.Vector([ti.cast(s.params[p_gravity + d], ti.f64) for d in ti.static(range(dim))])
                r, weight = arm(s, base, vec(s, base + HINGED_MASS_CENTRE, dim)), s.bodies[base + MASS] * g
                if ti.static(dim == 2):
                    torque[2] = cross2(r, weight)
                else:
                    torque = r.cross(weight)
            return torque


        @ti.func
        def inverse_inertia(s: ti.template(), base):
            return ti.Matrix([[s.bodies[base + INV_INERTIA + 3 * r + c] for c in ti.static(range(3))]
                              for r in ti.static(range(3))], dt=ti.f64)

        @ti.func
        def world_omega(s: ti.template(), base, quat, L):
            """omega = R I^-1 R^T L."""
            conj = ti.Vector([quat[0], -quat[1], -quat[2], -quat[3]])
            return rotate_q(quat, inverse_inertia(s, base) @ rotate_q(conj, L))

        @ti.func
        def world_inertia(s: ti.template(), base, quat, w):
            """L = R I R^T omega (I from its stored inverse)."""
            conj = ti.Vector([quat[0], -quat[1], -quat[2], -quat[3]])
            return rotate_q(quat, inverse_inertia(s, base).inverse() @ rotate_q(conj, w))

        @ti.func
        def body(s: ti.template(), t_target):
            ti.static(TRACED.add((self.name, "body motion")))
            n = s.sizes[st.N_PARTICLES]
            if s.status[st.IDLE] > 0.0:
                n = 0
            dt = s.status[st.DT]
            # the force on each body's particles, from S (a prescribed body's for its probe)
            for i in range(n):
                if s.Si[q.kind, i] == WALL and s.Si[q.body, i] > 0:
                    acc = ti.Vector.zero(real, dim)
                    grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[p_support2], gatherer, acc)
                    s.Sv[q.body_force, i] = acc
            ti.loop_config(serialize=True)
            for _ in range(1):
                if n > 0:
                    for b in ti.static(range(n_bodies)):
                        base = b * BODY_COLS
                        for d in ti.static(range(6)):
                            s.bodies[base + FORCE + d] = 0.0
                        if ti.static(integrator == "pc" and motions[b] == "floating"):
                            predict_pose(s, base, dt)
                    for i in range(n):
                        k = s.Si[q.body, i]
                        if k > 0 and s.Si[q.kind, i] == WALL:
                            base = (k - 1) * BODY_COLS
                            f = ti.cast(s.Sv[q.body_force, i], ti.f64)
                            r = arm(s, base, ti.cast(s.Sv[q.body_offset, i], ti.f64))
                            for d in ti.static(range(dim)):
                                s.bodies[base + FORCE + d] += f[d]
                            if ti.static(dim == 2):
                                s.bodies[base + TORQUE + 2] += cross2(r, f)
                            else:
                                torque = r.cross(f)
                                for d in ti.static(range(3)):
                                    s.bodies[base + TORQUE + d] += torque[d]
                    for b in ti.static(range(n_bodies)):
                        base = b * BODY_COLS
                        if ti.static(motions[b] == "floating"):
                            torque = vec(s, base + TORQUE, 3)
                            if ti.static(hinged[b]):  # gravity turns it about the hinge
                                torque += gravity_torque(s, base)
                            advance(s, base, dt, vec(s, base + FORCE, dim), torque)
                        elif ti.static(motions[b] == "prescribed"):
                            row = prescribed(s, base, s.status[st.TIME])
                            pos = ti.Vector([row[d] for d in ti.static(range(dim))])
                            put(s, base + CENTRE, vec(s, base + PIVOT, dim) + pos)
                            put(s, base + VELOCITY, ti.Vector([row[dim + 1 + d] for d in ti.static(range(dim))]))
                            put(s, base + ACC, ti.Vector([row[2 * dim + 2 + d] for d in ti.static(range(dim))]))
                            angle, w, alpha = row[dim], row[2 * dim + 1], row[3 * dim + 2]
                            if ti.static(dim == 2):
                                s.bodies[base + ORIENTATION] = angle
                                s.bodies[base + OMEGA + 2] = w
                                s.bodies[base + ALPHA + 2] = alpha
                            else:
                                axis = vec(s, base + AXIS, 3)
                                sh = ti.sin(0.5 * angle)
                                put(s, base + ORIENTATION, ti.Vector([ti.cos(0.5 * angle), sh * axis[0],
                                                                      sh * axis[1], sh * axis[2]]))
                                put(s, base + OMEGA, w * axis)
                                put(s, base + ALPHA, alpha * axis)
            for i in range(n):
                if s.Ci[q.body, i] > 0 and s.Ci[q.kind, i] == WALL:
                    place(s, i)

        return body
