"""The bodies' launch after the force pass (:meth:`taisph.terms.rigid_bodies.RigidBodies.after_force`):
the fluid's and contacts' force on every body particle (parallel), each body's motion
(serial, in cell order: reproducible), then every body particle placed on its body
(parallel). The equations: :mod:`.rigid_bodies`; each body's record: :mod:`.rigid_body_record`.

A floating body advances by its fluid's integrator's rule, the ``rigid_*`` methods of
:mod:`taisph.engine.integrators`: the velocity (2D: angular velocity; 3D: angular momentum)
by ``rigid_velocity``, the position (2D: angle) by ``rigid_displacement``, the 3D
orientation turned by ``rigid_turn_rate``; ``rigid_turn`` says when the orientation
advances: after the force pass, or (:data:`~taisph.engine.integrators.TURN_PREDICTED`)
before the torque is summed, so that the torque's lever arms are taken where the
predictor put the particles (velocity Verlet: the energy stays bounded, docs/bodies.md).
"""

import taichi as ti

from ..engine import status as st
from ..engine.integrators import TURN_END, TURN_PREDICTED
from ..engine.layout import WALL
from .rigid_body_forces import BodyForce, cross2, perp, rotate_q, turned
from .rigid_body_record import BODY, bodies_of


@ti.data_oriented
class BodyMotion:
    """The compile-time values of a scene's bodies (their motions, hinges, the integrator,
    the rows of the quantities) and the device functions that move them; :meth:`step` is
    the launch's body."""

    def __init__(self, term, solver):
        self.q, self.grid, self.dim, self.real = term.q, solver.grid, term.dim, solver.real
        self.motions, self.hinged = term.motions, term.hinged
        self.integrator = solver.integrator
        self.predicted = solver.integrator.rigid_turn == TURN_PREDICTED
        self.turn_at_end = solver.integrator.rigid_turn == TURN_END
        self.gatherer = BodyForce(solver)
        self.p_support2 = solver.param_rows["support2"]
        self.p_gravity, self.acc_prev = term.p_gravity, term.acc_prev_row
        self.n_table = 3 * (self.dim + 1)  # a table's row: offset (dim), angle; their rates; their accelerations

    # --- the record's numbers (every access to the bodies field) ----------------------
    @ti.func
    def get(self, s: ti.template(), at):
        return ti.static(bodies_of(s))[at]

    @ti.func
    def set(self, s: ti.template(), at, value):
        ti.static(bodies_of(s))[at] = value

    @ti.func
    def add(self, s: ti.template(), at, value):
        ti.static(bodies_of(s))[at] += value

    @ti.func
    def vec(self, s: ti.template(), at, n: ti.template()):
        return ti.Vector([ti.static(bodies_of(s))[at + d] for d in ti.static(range(n))], dt=ti.f64)

    @ti.func
    def put(self, s: ti.template(), at, v):
        for d in ti.static(range(v.n)):
            ti.static(bodies_of(s))[at + d] = v[d]

    # --- kinematics -------------------------------------------------------------------
    @ti.func
    def arm(self, s: ti.template(), base, r0):
        """R r0 of the body at record `base`."""
        r = r0
        if ti.static(self.dim == 2):
            a = self.get(s, base + BODY.orientation)
            c, sn = ti.cos(a), ti.sin(a)
            r = ti.Vector([c * r0[0] - sn * r0[1], sn * r0[0] + c * r0[1]], dt=ti.f64)
        else:
            r = rotate_q(self.vec(s, base + BODY.orientation, 4), r0)
        return r

    @ti.func
    def gravity(self, s: ti.template()):
        """The scene's gravity (zero without), f64."""
        g = ti.Vector.zero(ti.f64, self.dim)
        if ti.static(self.p_gravity >= 0):
            g = ti.Vector([ti.cast(s.params[self.p_gravity + d], ti.f64) for d in ti.static(range(self.dim))])
        return g

    @ti.func
    def place(self, s: ti.template(), i):
        """Body particle i on its body: x = c + R r0, v = V + omega x r, a = A + alpha x r + omega x (omega x r)."""
        q = ti.static(self.q)
        base = (s.Ci[q.body, i] - 1) * BODY.cols
        r = self.arm(s, base, ti.cast(s.Cv[q.body_offset, i], ti.f64))
        x = self.vec(s, base + BODY.centre, self.dim) + r
        v = self.vec(s, base + BODY.velocity, self.dim)
        a = self.vec(s, base + BODY.acc, self.dim)
        if ti.static(self.dim == 2):
            w, alpha = self.get(s, base + BODY.omega + 2), self.get(s, base + BODY.alpha + 2)
            v += perp(w, r)
            a += perp(alpha, r) - w * w * r
        else:
            w, alpha = self.vec(s, base + BODY.omega, 3), self.vec(s, base + BODY.alpha, 3)
            v += w.cross(r)
            a += alpha.cross(r) + w.cross(w.cross(r))
        s.Cv[q.position, i] = ti.cast(x, self.real)
        s.Cv[q.velocity, i] = ti.cast(v, self.real)
        s.Cv[q.wall_acceleration, i] = ti.cast(a, self.real)
        if ti.static(self.acc_prev >= 0):  # the predictor then moves it along its curve
            s.Cv[self.acc_prev, i] = ti.cast(a, self.real)

    # --- prescribed bodies --------------------------------------------------------------
    @ti.func
    def table_row(self, s: ti.template(), base, t):
        """Pose, rates and accelerations of a prescribed body at time t from its table."""
        n_table = ti.static(self.n_table)
        offset = ti.cast(self.get(s, base + BODY.table_offset), ti.i32)
        length = ti.cast(self.get(s, base + BODY.table_length), ti.i32)
        x = t / self.get(s, base + BODY.table_dt)
        k = ti.min(ti.max(ti.cast(ti.floor(x), ti.i32), 0), length - 2)  # the last interval ends the table
        frac = ti.min(ti.max(x - k, 0.0), 1.0)
        settled = x > length - 1  # (at its last time exactly: still its last row's rates)
        row = ti.Vector.zero(ti.f64, n_table)
        for c in ti.static(range(n_table)):
            a = self.get(s, offset + k * n_table + c)
            b = self.get(s, offset + (k + 1) * n_table + c)
            row[c] = a + frac * (b - a)
        if settled:  # past the table's end: at rest at its last pose
            for c in ti.static(range(n_table // 3, n_table)):
                row[c] = 0.0
        return row

    @ti.func
    def follow_table(self, s: ti.template(), base):
        """A prescribed body's state at the step's end time, from its table."""
        dim = ti.static(self.dim)
        row = self.table_row(s, base, s.status[st.TIME])
        pos = ti.Vector([row[d] for d in ti.static(range(dim))])
        self.put(s, base + BODY.centre, self.vec(s, base + BODY.pivot, dim) + pos)
        self.put(s, base + BODY.velocity, ti.Vector([row[dim + 1 + d] for d in ti.static(range(dim))]))
        self.put(s, base + BODY.acc, ti.Vector([row[2 * dim + 2 + d] for d in ti.static(range(dim))]))
        angle, w, alpha = row[dim], row[2 * dim + 1], row[3 * dim + 2]
        if ti.static(dim == 2):
            self.set(s, base + BODY.orientation, angle)
            self.set(s, base + BODY.omega + 2, w)
            self.set(s, base + BODY.alpha + 2, alpha)
        else:
            axis = self.vec(s, base + BODY.axis, 3)
            sh = ti.sin(0.5 * angle)
            self.put(s, base + BODY.orientation, ti.Vector([ti.cos(0.5 * angle), sh * axis[0],
                                                            sh * axis[1], sh * axis[2]]))
            self.put(s, base + BODY.omega, w * axis)
            self.put(s, base + BODY.alpha, alpha * axis)

    # --- floating bodies: Newton-Euler by the integrator's rule -------------------------
    @ti.func
    def advance_linear(self, s: ti.template(), base, dt, force):
        """M dV/dt = F + M g over dt: the reference point's velocity and position."""
        dim = ti.static(self.dim)
        acc = (force / self.get(s, base + BODY.mass) + self.gravity(s)) * self.vec(s, base + BODY.free_linear, dim)
        v0 = self.vec(s, base + BODY.velocity, dim)
        a0 = self.vec(s, base + BODY.acc_prev, dim)
        v1 = self.integrator.rigid_velocity(v0, a0, acc, dt)
        dx = self.integrator.rigid_displacement(v0, v1, a0, dt)
        self.put(s, base + BODY.centre, self.vec(s, base + BODY.centre, dim) + dx)
        self.put(s, base + BODY.velocity, v1)
        self.put(s, base + BODY.acc_prev, acc)
        self.put(s, base + BODY.acc, acc)

    @ti.func
    def advance_angle(self, s: ti.template(), base, dt, torque):
        """2D: I domega/dt = T about z over dt (the angle: by the predictor, if it turns it)."""
        free_r = self.get(s, base + BODY.free_rotation)
        alpha = torque[2] * self.get(s, base + BODY.inv_inertia) * free_r
        w0, al0 = self.get(s, base + BODY.omega + 2), self.get(s, base + BODY.alpha_prev + 2)
        w1 = self.integrator.rigid_velocity(w0, al0, alpha, dt)
        if ti.static(not self.predicted):
            self.add(s, base + BODY.orientation, self.integrator.rigid_displacement(w0, w1, al0, dt))
        self.set(s, base + BODY.omega + 2, w1)
        self.set(s, base + BODY.alpha_prev + 2, alpha)
        self.set(s, base + BODY.alpha + 2, alpha)

    @ti.func
    def advance_momentum(self, s: ti.template(), base, dt, torque):
        """3D: dL/dt = T over dt, omega = R I^-1 R^T L (the orientation: by the predictor, if it turns it)."""
        free_r = self.vec(s, base + BODY.free_rotation, 3)
        t0 = self.vec(s, base + BODY.alpha_prev, 3)  # 3D: the last step's torque
        L = self.vec(s, base + BODY.momentum, 3)
        L1 = self.integrator.rigid_velocity(L, t0, torque, dt)
        quat = self.vec(s, base + BODY.orientation, 4)
        w0 = self.vec(s, base + BODY.omega, 3)
        if ti.static(not self.predicted):
            w_end = w0
            if ti.static(self.turn_at_end):
                w_end = self.world_omega(s, base, quat, L1) * free_r
            quat = turned(quat, self.integrator.rigid_turn_rate(w0, w_end, self.vec(s, base + BODY.alpha, 3), dt), dt)
        w1 = self.world_omega(s, base, quat, L1) * free_r
        if free_r.min() < 0.5:  # a constrained axis holds no momentum along it
            L1 = self.world_inertia(s, base, quat, w1)
        self.put(s, base + BODY.orientation, quat)
        self.put(s, base + BODY.momentum, L1)
        self.put(s, base + BODY.omega, w1)
        self.put(s, base + BODY.alpha_prev, torque)
        if dt > 0.0:  # (the zero-length bootstrap step keeps it: w1 - w0 is round-off there)
            self.put(s, base + BODY.alpha, (w1 - w0) / dt)

    @ti.func
    def predict_pose(self, s: ti.template(), base, dt):
        """The orientation at the step's end, where the predictor put its particles, set
        before the torque's sum takes its lever arms (docs/bodies.md)."""
        if ti.static(self.dim == 2):
            w0, al0 = self.get(s, base + BODY.omega + 2), self.get(s, base + BODY.alpha_prev + 2)
            self.add(s, base + BODY.orientation, self.integrator.rigid_displacement(w0, w0, al0, dt))
        else:
            w0 = self.vec(s, base + BODY.omega, 3)
            rate = self.integrator.rigid_turn_rate(w0, w0, self.vec(s, base + BODY.alpha, 3), dt)
            self.put(s, base + BODY.orientation, turned(self.vec(s, base + BODY.orientation, 4), rate, dt))

    @ti.func
    def gravity_torque(self, s: ti.template(), base):
        """(R r_c) x M g of a hinged body, r_c its centre of mass from the hinge."""
        torque = ti.Vector.zero(ti.f64, 3)
        if ti.static(self.p_gravity >= 0):
            r = self.arm(s, base, self.vec(s, base + BODY.hinged_mass_centre, self.dim))
            weight = self.get(s, base + BODY.mass) * self.gravity(s)
            if ti.static(self.dim == 2):
                torque[2] = cross2(r, weight)
            else:
                torque = r.cross(weight)
        return torque

    @ti.func
    def inverse_inertia(self, s: ti.template(), base):
        return ti.Matrix([[self.get(s, base + BODY.inv_inertia + 3 * r + c) for c in ti.static(range(3))]
                          for r in ti.static(range(3))], dt=ti.f64)

    @ti.func
    def world_omega(self, s: ti.template(), base, quat, L):
        """omega = R I^-1 R^T L."""
        conj = ti.Vector([quat[0], -quat[1], -quat[2], -quat[3]])
        return rotate_q(quat, self.inverse_inertia(s, base) @ rotate_q(conj, L))

    @ti.func
    def world_inertia(self, s: ti.template(), base, quat, w):
        """L = R I R^T omega (I from its stored inverse)."""
        conj = ti.Vector([quat[0], -quat[1], -quat[2], -quat[3]])
        return rotate_q(quat, self.inverse_inertia(s, base).inverse() @ rotate_q(conj, w))

    # --- the launch -----------------------------------------------------------------------
    @ti.func
    def gather_forces(self, s: ti.template(), n):
        """The force on each body particle from its neighbours in S (a prescribed body's for its probe)."""
        q = ti.static(self.q)
        for i in range(n):
            if s.Si[q.kind, i] == WALL and s.Si[q.body, i] > 0:
                acc = ti.Vector.zero(self.real, self.dim)
                self.grid.for_each_neighbour(s, i, s.Sv[q.position, i], s.params[self.p_support2], self.gatherer, acc)
                s.Sv[q.body_force, i] = acc

    @ti.func
    def sum_forces(self, s: ti.template(), n):
        """Each body's force and torque: the sum over its particles, serially in cell order."""
        q = ti.static(self.q)
        for i in range(n):
            k = s.Si[q.body, i]
            if k > 0 and s.Si[q.kind, i] == WALL:
                base = (k - 1) * BODY.cols
                f = ti.cast(s.Sv[q.body_force, i], ti.f64)
                r = self.arm(s, base, ti.cast(s.Sv[q.body_offset, i], ti.f64))
                for d in ti.static(range(self.dim)):
                    self.add(s, base + BODY.force + d, f[d])
                if ti.static(self.dim == 2):
                    self.add(s, base + BODY.torque + 2, cross2(r, f))
                else:
                    torque = r.cross(f)
                    for d in ti.static(range(3)):
                        self.add(s, base + BODY.torque + d, torque[d])

    @ti.func
    def start_bodies(self, s: ti.template(), dt):
        """Each body's force and torque zeroed; the predicted orientations (if the integrator predicts them)."""
        for b in ti.static(range(len(self.motions))):
            base = b * BODY.cols
            for d in ti.static(range(6)):  # force and torque
                self.set(s, base + BODY.force + d, 0.0)
            if ti.static(self.predicted and self.motions[b] == "floating"):
                self.predict_pose(s, base, dt)

    @ti.func
    def move_bodies(self, s: ti.template(), dt):
        """Every body over the step, its force and torque summed."""
        for b in ti.static(range(len(self.motions))):
            base = b * BODY.cols
            if ti.static(self.motions[b] == "floating"):
                torque = self.vec(s, base + BODY.torque, 3)
                if ti.static(self.hinged[b]):  # gravity turns it about the hinge
                    torque += self.gravity_torque(s, base)
                self.advance_linear(s, base, dt, self.vec(s, base + BODY.force, self.dim))
                if ti.static(self.dim == 2):
                    self.advance_angle(s, base, dt, torque)
                else:
                    self.advance_momentum(s, base, dt, torque)
            elif ti.static(self.motions[b] == "prescribed"):
                self.follow_table(s, base)

    @ti.func
    def step(self, s: ti.template()):
        """The launch: forces gathered (parallel), bodies moved (serial), particles placed (parallel).

        Taichi compiles with fast math, which lets the compiler regroup sums: where a value
        such as dt is copied into a function's argument shapes the machine code, and with
        it the last bit of a result. The serial part's three calls each take dt: wrapped
        in one function taking it once, they compile to 3D turns that differ in the last
        bit, and runs no longer repeat earlier ones (fingerprints, checkpoints) bit for bit."""
        q = ti.static(self.q)
        n = s.sizes[st.N_PARTICLES]
        if s.status[st.IDLE] > 0.0:
            n = 0
        dt = s.status[st.DT]
        self.gather_forces(s, n)
        ti.loop_config(serialize=True)
        for _ in range(1):
            if n > 0:
                self.start_bodies(s, dt)
                self.sum_forces(s, n)
                self.move_bodies(s, dt)
        for i in range(n):
            if s.Ci[q.body, i] > 0 and s.Ci[q.kind, i] == WALL:
                self.place(s, i)
