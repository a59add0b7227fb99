"""The forces on a body's particles: the fluid's, gathered from the force pass's own pair
terms, and contact with walls and other bodies (:mod:`.rigid_bodies` sums them per body);
the rotations the bodies' kernel uses.

**Contact** (a floating body against walls and other bodies): a normal spring-dashpot
between particles closer than the contact distance d_c (the particle spacing: the
distance of two surfaces' particle rows when they touch),

    F = m_pair [ k (d_c - d) - 2 zeta sqrt(k) (v_rel . n) ] n,   d < d_c,

with k = ``contact_stiffness`` (1/s^2, default (0.3 c0 / h)^2: stiff on the flow's
acoustic time scale, within the step's stability) and zeta = ``contact_damping``
(default 1, critical), m_pair the body's mass per particle (the reduced mass for two
floating bodies): no tunnelling, no friction (a documented simplification).

**The fluid's contact with a body** (:func:`fluid_contact`, in the force pass): a fluid
particle closer than d_c / 2 to a body particle is pushed off it by the same law, per
unit mass, pushing only,

    a_f = max(0, k (d_c / 2 - d) - 2 zeta sqrt(k) (v_f - v_w) . n) n,

and the body gets minus m_f a_f (gathered like the fluid's other pair forces). Dummy walls
hold water off only by the pressure they extrapolate from it: a droplet left on a body's
dry top has next to none, so gravity settled such particles onto the body's particles and
through its surface row (docs/bodies.md, "Water entry").
"""

import taichi as ti

from ..engine.layout import FLUID
from .rigid_body_record import BODY, MOTIONS, bodies_of


@ti.func
def cross2(a, b):
    return a[0] * b[1] - a[1] * b[0]


@ti.func
def perp(w, r):
    """omega x r in 2D, omega the scalar rate about z."""
    return ti.Vector([-w * r[1], w * r[0]])


@ti.func
def rotate_q(q, v):
    """v rotated by the unit quaternion q = (w, x, y, z)."""
    u = ti.Vector([q[1], q[2], q[3]])
    t = 2.0 * u.cross(v)
    return v + q[0] * t + u.cross(t)


@ti.func
def q_mul(a, b):
    return ti.Vector([a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                      a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                      a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                      a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]])


@ti.func
def fluid_contact(s: ti.template(), q: ti.template(), p: ti.template(), i, j, rij, r, rates: ti.template()):
    """The push on the fluid particle i from the body particle j (none from other neighbours)."""
    if s.Si[q.body, j] > 0 and s.Si[q.kind, j] != FLUID:
        reach = 0.5 * s.params[p.contact_distance]
        if 0.0 < r < reach:
            n = rij / r
            k = s.params[p.contact_stiffness]
            closing = (s.Sv[q.velocity, i] - s.Sv[q.velocity, j]).dot(n)
            push = k * (reach - r) - 2.0 * s.params[p.contact_damping] * ti.sqrt(k) * closing
            if push > 0.0:
                rates.acc += push * n


@ti.func
def turned(quat, w, dt):
    """The orientation `quat` turned by the rate w over dt (exact for a constant rate), normalised."""
    angle = w.norm() * dt
    turn = ti.Vector([1.0, 0.0, 0.0, 0.0], dt=ti.f64)
    if angle > 0.0:
        axis = w / w.norm()
        sh = ti.sin(0.5 * angle)
        turn = ti.Vector([ti.cos(0.5 * angle), sh * axis[0], sh * axis[1], sh * axis[2]], dt=ti.f64)
    out = q_mul(turn, quat)
    return out / out.norm()


@ti.data_oriented
class BodyForce:
    """Neighbour visitor: the force on body particle i (the wall) from its fluid
    neighbours through every pair term, and from the contact spring-dashpot."""

    def __init__(self, solver):
        self.q = solver.layout.q
        self.kern = solver.kernel
        self.terms = [t for t in solver.terms if t.has_pair]
        self.p_inv_h = solver.param_rows["inv_h"]
        self.p_grad_norm = solver.param_rows["grad_norm"]
        self.p_k = solver.param_rows["contact_stiffness"]
        self.p_zeta = solver.param_rows["contact_damping"]
        self.p_dc = solver.param_rows["contact_distance"]
        self.Rates = solver.Rates
        self.real, self.dim = solver.real, solver.dim
        self.floating = MOTIONS["floating"]

    @ti.func
    def visit(self, s: ti.template(), w, j, rwj, r2, acc: ti.template()):
        q = ti.static(self.q)
        r = ti.sqrt(r2)
        if s.Si[q.kind, j] == FLUID:
            rjw = -rwj  # the force pass's r_ij = x_f - x_w (negation is exact: the same bits)
            grad = (s.params[self.p_grad_norm] * self.kern.g(r * s.params[self.p_inv_h])) * rjw
            rates = self.Rates(acc=ti.Vector.zero(self.real, self.dim))
            for t in ti.static(self.terms):
                t.pair(s, j, w, rjw, r, grad, rates)
            acc -= s.Ss[q.mass, j] * rates.acc
        elif (s.Si[q.body, j] != s.Si[q.body, w] and r < s.params[self.p_dc] and r > 0.0
              and ti.static(bodies_of(s))[(s.Si[q.body, w] - 1) * BODY.cols + BODY.motion] == self.floating):
            mine = (s.Si[q.body, w] - 1) * BODY.cols
            m = ti.static(bodies_of(s))[mine + BODY.particle_mass]
            other = s.Si[q.body, j]
            if other > 0:
                base = (other - 1) * BODY.cols
                if ti.static(bodies_of(s))[base + BODY.motion] == self.floating:
                    mj = ti.static(bodies_of(s))[base + BODY.particle_mass]
                    m = m * mj / (m + mj)
            n = rwj / r
            k = s.params[self.p_k]
            closing = (s.Sv[q.velocity, w] - s.Sv[q.velocity, j]).dot(n)
            push = m * (k * (s.params[self.p_dc] - r) - 2.0 * s.params[self.p_zeta] * ti.sqrt(k) * closing)
            acc += ti.cast(push, self.real) * n
