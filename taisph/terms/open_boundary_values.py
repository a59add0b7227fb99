"""The values of an open boundary's buffer particles: a zone's prescribed velocity from its
table, the fluid's pressure and velocity near the face by a first-order fit, and, without
viscosity, the uniform speed of water moving in (:mod:`taisph.terms.open_boundary` says
how they are used)."""

import taichi as ti

from ..engine import status as st
from ..engine.kernels import TRACED
from ..engine.layout import FLUID

PRESCRIBED, EXTRAPOLATED = "prescribed", "extrapolated"  # a zone's velocity or pressure


@ti.func
def table_velocity(s: ti.template(), r: ti.template(), dim: ti.template(), x, t):
    """Zone z's prescribed velocity at x and time t: its table, interpolated
    (linearly in time and along each face axis)."""
    origin = ti.Vector([s.params[r.origin + d] for d in ti.static(range(dim))])
    rel = x - origin
    shape = [ti.cast(s.params[r.table_shape + k], ti.i32) for k in ti.static(range(dim))]
    n_t, n_1 = shape[0], shape[1]
    n_2 = 1
    if ti.static(dim == 3):
        n_2 = shape[2]
    # fractional indices in time and along the axes
    period = s.params[r.period]
    tt = t
    if period > 0.0:
        tt = t - period * ti.floor(t / period)
    ft = 0.0
    if n_t > 1:
        ft = ti.min(ti.max(tt / s.params[r.table_dt], 0.0), n_t - 1.0)
    f = ti.Vector([0.0, 0.0])
    for k in ti.static(range(dim - 1)):
        axis = ti.Vector([s.params[(r.axis1, r.axis2)[k] + d] for d in ti.static(range(dim))])
        count = n_1 if k == 0 else n_2
        if count > 1:
            frac = rel.dot(axis) / s.params[(r.length1, r.length2)[k]]
            f[k] = ti.min(ti.max(frac, 0.0), 1.0) * (count - 1.0)
    k_t = ti.min(ti.cast(ft, ti.i32), ti.max(n_t - 2, 0))  # the interval's first sample along each
    k_1 = ti.min(ti.cast(f[0], ti.i32), ti.max(n_1 - 2, 0))
    k_2 = ti.min(ti.cast(f[1], ti.i32), ti.max(n_2 - 2, 0))
    w_t, w_1, w_2 = ft - k_t, f[0] - k_1, f[1] - k_2
    base = ti.cast(s.params[r.table_offset], ti.i32)
    value = ti.Vector.zero(s.Sv.dtype, dim)
    for c in ti.static(range(8)):
        dt_, d1, d2 = c & 1, (c >> 1) & 1, (c >> 2) & 1
        wt = w_t if dt_ else 1.0 - w_t
        w1 = w_1 if d1 else 1.0 - w_1
        w2 = w_2 if d2 else 1.0 - w_2
        weight = wt * w1 * w2
        if weight != 0.0:
            row = ((ti.min(k_t + dt_, n_t - 1) * n_1 + ti.min(k_1 + d1, n_1 - 1)) * n_2
                   + ti.min(k_2 + d2, n_2 - 1)) * dim
            for d in ti.static(range(dim)):
                value[d] += weight * s.store.tables[base + row + d]
    return value


@ti.data_oriented
class Fit:
    """Neighbour visitor of the buffer pass: the moments of a first-order (linear)
    least-squares fit of the fluid's pressure and velocity around the point x_r, over
    the fluid (not other buffer particles) within a support of it: with phi = (1, r/h),
    r = x_j - x_r, M = sum W phi phi^T and b_q = sum W q_j phi; acc holds M's
    (1 + dim)^2 entries, then b for q = p, v_x, v_y(, v_z)."""

    def __init__(self, q, kern, p_inv_h, p_w_norm, dim):
        self.q, self.kern, self.p_inv_h, self.p_w_norm, self.dim = q, kern, p_inv_h, p_w_norm, dim

    @ti.func
    def visit(self, s: ti.template(), i, j, rij, r2, acc: ti.template()):
        q = ti.static(self.q)
        dim = ti.static(self.dim)
        n = ti.static(dim + 1)
        if s.Si[q.kind, j] == FLUID and s.Si[q.open_zone, j] == 0:
            w = s.params[self.p_w_norm] * self.kern.f(ti.sqrt(r2) * s.params[self.p_inv_h])
            phi = ti.Vector([1.0] + [-rij[d] * s.params[self.p_inv_h] for d in ti.static(range(dim))])
            v = s.Sv[q.velocity, j]
            values = ti.Vector([s.Ss[q.pressure, j]] + [v[d] for d in ti.static(range(dim))])
            for a in ti.static(range(n)):
                for b in ti.static(range(n)):
                    acc[a * n + b] += w * phi[a] * phi[b]
            for k in ti.static(range(n)):
                for a in ti.static(range(n)):
                    acc[n * n + k * n + a] += w * values[k] * phi[a]


@ti.func
def fitted(acc: ti.template(), dim: ti.template()):
    """(pressure, velocity) at x_r from the moments of :class:`_Mirror`: the linear fit
    (exact for linear fields; no one-sided bias by a wall or the face), or the Shepard
    mean where the fluid around x_r is too sparse for a fit (Tafuni et al. 2018 use the
    same first-order interpolation)."""
    n = ti.static(dim + 1)
    M = ti.Matrix([[acc[a * n + b] for b in ti.static(range(n))] for a in ti.static(range(n))])
    result = ti.Vector([acc[n * n + k * n] / acc[0] for k in ti.static(range(n))])  # Shepard
    if ti.abs(M.determinant()) > 1e-3 * acc[0] ** n:
        inverse = M.inverse()
        for k in ti.static(range(n)):
            value = 0.0
            for b in ti.static(range(n)):
                value += inverse[0, b] * acc[n * n + k * n + b]
            result[k] = value
    return result[0], ti.Vector([result[1 + d] for d in ti.static(range(dim))])


@ti.func
def uniform_inflow_speed(s: ti.template(), q: ti.template(), rows: ti.template(), modes: ti.template(),
                         dim: ti.template(), speeds: ti.template(), i, assign: ti.template()):
    """Without viscosity (the buffer pass of :class:`taisph.terms.open_boundary.OpenBoundaries`),
    for buffer particle i of a zone that extrapolates the velocity: its normal speed added to
    its zone's sum (`assign` False; zone z's sum and count in status slots ``speeds + 2 z`` and
    the next), or, if it moves in, the zone's mean normal speed given to
    it (`assign` True; the mean if that is inward, else it stands), so that water enters such
    a face as one uniform stream. Euler's equations need an inflow's profile given;
    extrapolated, each line of the buffer carried its own speed into the fluid its next fit
    read, and the lines ran apart into jets (docs/open_boundaries.md, "Inflow through an
    extrapolated zone")."""
    ti.static(TRACED.add(("open_boundaries", "uniform inflow")))
    zone = s.Si[q.open_zone, i]
    if s.Si[q.kind, i] == FLUID and zone > 0:
        for z in ti.static(range(len(rows))):
            if ti.static(modes[z][0] == EXTRAPOLATED):
                if zone == z + 1:
                    normal = ti.Vector([s.params[rows[z].normal + d] for d in ti.static(range(dim))])
                    speed = s.Sv[q.velocity, i].dot(normal)
                    total, count = speeds + 2 * z, speeds + 2 * z + 1
                    if ti.static(assign):
                        if speed > 0.0:
                            s.Sv[q.velocity, i] = ti.max(s.status[total] / ti.max(s.status[count], 1.0), 0.0) * normal
                    else:
                        s.status[total] += speed
                        s.status[count] += 1.0
