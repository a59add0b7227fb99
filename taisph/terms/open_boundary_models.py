"""The models of an open boundary's buffer values: what imposes a zone's velocity and its
pressure (:mod:`taisph.terms.open_boundary` runs them in its buffer pass).

A zone has one velocity model and one pressure model, chosen by its ``velocity`` and
``pressure`` arguments (a value or a table: prescribed; none: extrapolated from the
fluid). Each model is a class with one ``ti.func``, compiled only into zones that use it:

- a velocity model's ``velocity(s, at, pressure_model)`` gives buffer particle
  ``at.i``'s velocity;
- a pressure model's ``pressure(s, at, velocity_model, v)`` its pressure, knowing the
  velocity ``v`` just imposed.

``at`` (:class:`Buffer`) holds what the pass knows of the particle: its position, the
time, its zone's runtime rows, the face's normal and the particle's signed distance from
the face (positive into the fluid), and the first-order fit of the fluid around its
mirror point (``fitted``: any fluid there; ``p_fluid``, ``v_fluid``: the fit, else the
particle's own values). The two models may read each other's kind (``prescribed``) and
target (``target(s, at)``): the characteristic that leaves the fluid through a face,
``u_n - p / (rho0 c0)``, ties a prescribed value of one to the other.

A new model (e.g. one based on the method of characteristics) is a new class with the
same ``ti.func`` and a ``prescribed`` flag, added to :data:`VELOCITY_MODELS` or
:data:`PRESSURE_MODELS` under the name a zone's mode takes.
"""

import taichi as ti

from .open_boundary_values import EXTRAPOLATED, PRESCRIBED, table_velocity


def buffer_type(dim: int, real):
    """The struct of what the buffer pass knows of one particle (see the module docstring),
    for the dimension and precision of a solver."""
    vec = ti.types.vector(dim, real)
    return ti.types.struct(i=ti.i32, x=vec, time=ti.f64, normal=vec, distance=real, fitted=ti.i32,
                           p_fluid=real, v_fluid=vec)


class _Model:
    """A model bound to its zone at compile time: the term's rows (``q``, ``m``: particle
    and material rows), the zone's runtime parameter rows ``r``, the dimension, and the
    parameter row of the smoothing length."""

    prescribed = False

    def __init__(self, term, zone: int, p_h: int):
        self.q, self.m, self.r, self.dim, self.p_h = term.q, term.m, term.rows[zone], term.dim, p_h

    @ti.func
    def impedance(self, s: ti.template(), i):
        """rho0 c0 of particle i's material: how a pressure answers a velocity at a face."""
        material = s.Si[self.q.material, i]
        return s.mat[material, self.m.rho0] * s.mat[material, self.m.c0]


@ti.data_oriented
class PrescribedVelocity(_Model):
    """The zone's table (a constant, a profile, a time table or a tabulated function),
    interpolated at the particle and the time (:func:`.open_boundary_values.table_velocity`)."""

    prescribed = True

    @ti.func
    def velocity(self, s: ti.template(), at: ti.template(), pressure_model: ti.template()):
        return table_velocity(s, self.r, self.dim, at.x, at.time)


@ti.data_oriented
class ExtrapolatedVelocity(_Model):
    """The normal part of the fluid's fitted velocity, v = (v_fluid . n) n: each line of the
    buffer moves as one along the normal, keeping the lattice. Beside a prescribed pressure
    p0 the characteristic leaving the fluid adds (p0 - p_fluid) / (rho0 c0), at most the
    fluid's own speed, so that the fluid pushes out (or draws in) what its pressure says."""

    @ti.func
    def velocity(self, s: ti.template(), at: ti.template(), pressure_model: ti.template()):
        v = s.Sv[self.q.velocity, at.i]
        if at.fitted:
            speed = at.v_fluid.dot(at.normal)
            if ti.static(pressure_model.prescribed):
                extra = (pressure_model.target(s, at) - at.p_fluid) / self.impedance(s, at.i)
                bound = ti.abs(speed)
                speed += ti.min(ti.max(extra, -bound), bound)
            v = speed * at.normal
        return v


@ti.data_oriented
class PrescribedPressure(_Model):
    """The zone's pressure p0 at the face, and the fluid's gradient across it: p linear through
    (face, p0) and (mirror point, p_fluid), p = p0 + (p0 - p_fluid) (-distance) / h, so that the
    face is where the pressure is p0."""

    prescribed = True

    @ti.func
    def target(self, s: ti.template(), at: ti.template()):
        return s.params[self.r.pressure]

    @ti.func
    def pressure(self, s: ti.template(), at: ti.template(), velocity_model: ti.template(), v):
        p0 = self.target(s, at)
        p = p0
        if at.fitted:
            p = p0 + (p0 - at.p_fluid) * (-at.distance) / s.params[self.p_h]
        return p


@ti.data_oriented
class ExtrapolatedPressure(_Model):
    """The fluid's fitted pressure (zero normal gradient across the buffer). Beside a
    prescribed velocity the same characteristic adds rho0 c0 (v - v_fluid) . n: a buffer that
    moves away from the fluid faster than the fluid follows draws it by a lower pressure."""

    @ti.func
    def pressure(self, s: ti.template(), at: ti.template(), velocity_model: ti.template(), v):
        p = at.p_fluid  # (the particle's own pressure where no fluid was fitted)
        if ti.static(velocity_model.prescribed):
            p = at.p_fluid + self.impedance(s, at.i) * (v - at.v_fluid).dot(at.normal)
        return p


VELOCITY_MODELS = {PRESCRIBED: PrescribedVelocity, EXTRAPOLATED: ExtrapolatedVelocity}
PRESSURE_MODELS = {PRESCRIBED: PrescribedPressure, EXTRAPOLATED: ExtrapolatedPressure}


def models(term, p_h: int) -> list:
    """(velocity model, pressure model) of each of the term's zones, bound to it."""
    return [(VELOCITY_MODELS[velocity](term, z, p_h), PRESSURE_MODELS[pressure](term, z, p_h))
            for z, (velocity, pressure) in enumerate(term.modes)]
