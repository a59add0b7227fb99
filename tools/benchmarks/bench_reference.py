"""A hand-fused Taichi dam break: the reference the engine's step is measured against.

    python -m tools.benchmarks.bench_reference --dim 2 --dx 0.01 --steps 200     # prints ns per particle-step
    python -m tools.benchmarks.bench_reference --check                           # agrees with taisph's engine?

Exactly the physics and integrator of the flagship dam break's defaults
(``taisph.cases.dam_break`` / ``dam_break_3d``; it refuses to run if they change): continuity and the symmetric pressure
gradient over fluid and dummy-wall neighbours; Monaghan artificial viscosity (alpha,
eta^2 = 0.01 h^2, walls with the no-slip ghost velocity); density diffusion (delta-SPH
with the hydrostatic correction, fluid neighbours); gravity; dummy walls with pressure,
density and ghost velocity extrapolated from the fluid (Adami et al. 2012); Tait EOS;
cubic spline; predictor-corrector; adaptive dt from the last step's maxima
(C_cfl h / max(c + |v|), C_force sqrt(h / max |a|)). It starts from the case's own
particles, so both do the same work.

Written the way a person would write one loop for this one physics, as fast as we
could make it: state in 1-D Taichi fields (fixed size), cell-sorted every step by a
counting sort, three launches per step, run back to back without a graph:

1. sort: dt, predictor, cell count, serial prefix sum, scatter to cell order, EOS;
2. walls: each wall particle's pressure, density and ghost velocity from the fluid;
3. force: every fluid particle's rates (one neighbour loop, parameters in registers),
   corrector, maxima for the next dt (read before the atomic).

``tools/benchmarks/bench.py`` runs it beside the engine in the same minute and prints the ratio.
"""

import argparse
import math
import time

import numpy as np
import taichi as ti

FLUID, WALL = 0, 1


def setup(scene, real=ti.f64, start_from=None):
    """Fields and kernels of the reference for `scene` (a taisph dam break); returns an
    object with step(n) and state(). `start_from`, if given, is a :class:`taisph.Simulation`
    of that scene: the reference starts from its time, positions, velocities and
    densities (its rates are evaluated there, as at t = 0), so both run the same flow."""
    dim = scene.dim
    n = scene.n
    water = scene.materials[0]
    rho0, c0, gamma = water.rho0, water.c0, water.gamma
    B = rho0 * c0 * c0 / gamma
    h = scene.smoothing_length
    support = 2.0 * h
    terms = scene.terms_by_name
    g_vec = np.asarray(terms["gravity"].values["gravity"], float)
    alpha = terms["artificial_viscosity"].values["alpha"]
    delta = terms["density_diffusion"].values["delta"]
    sigma = {2: 10.0 / (7.0 * math.pi), 3: 1.0 / math.pi}[dim]
    w_norm, grad_norm = sigma / h**dim, sigma / h ** (dim + 2)
    mass = float(scene.mass[0])
    assert np.all(scene.mass == mass)
    lo = np.asarray(scene.domain[0]) - support
    hi = np.asarray(scene.domain[1]) + support
    shape = [int(math.ceil((hi[d] - lo[d]) / support)) for d in range(dim)]
    n_cells = int(np.prod(shape))
    vec = ti.types.vector(dim, real)
    courant, force_factor = scene.courant or 0.25, 0.25

    # runtime parameters (changing one recompiles nothing, as in taisph), read into
    # registers once per particle by load()
    names = ("h", "support2", "w_norm", "grad_norm", "rho0", "c0", "gamma", "B", "alpha", "delta", "mass",
             "courant", "force_factor")
    Params = ti.types.struct(**{k: real for k in names}, gravity=vec, grid_lo=vec, inv_cell=vec)
    values = dict(h=h, support2=support * support, w_norm=w_norm, grad_norm=grad_norm, rho0=rho0, c0=c0,
                  gamma=gamma, B=B, alpha=alpha, delta=delta, mass=mass, courant=courant, force_factor=force_factor)
    prm = ti.field(real, len(names) + 3 * dim)
    prm.from_numpy(np.array([values[k] for k in names] + list(g_vec) + list(lo) + [1.0 / support] * dim))
    gshape_field = ti.field(ti.i32, dim)
    gshape_field.from_numpy(np.array(shape, np.int32))

    @ti.func
    def load():
        k = ti.static(len(names))
        return Params(**{name: prm[m] for m, name in enumerate(names)},
                      gravity=ti.Vector([prm[k + d] for d in ti.static(range(dim))]),
                      grid_lo=ti.Vector([prm[k + dim + d] for d in ti.static(range(dim))]),
                      inv_cell=ti.Vector([prm[k + 2 * dim + d] for d in ti.static(range(dim))]))

    x, v, a_prev = (ti.Vector.field(dim, real, n) for _ in range(3))
    rho, drho_prev = ti.field(real, n), ti.field(real, n)
    kind, ids = ti.field(ti.i32, n), ti.field(ti.i32, n)
    # cell-sorted copies (S) and what the sort derives per particle
    xs, vs, as_, vw = (ti.Vector.field(dim, real, n) for _ in range(4))
    rhos, drhos, p, p_rho2 = (ti.field(real, n) for _ in range(4))
    kinds, idss, cell_of = ti.field(ti.i32, n), ti.field(ti.i32, n), ti.field(ti.i32, n)
    count, start, fill = ti.field(ti.i32, n_cells), ti.field(ti.i32, n_cells + 1), ti.field(ti.i32, n_cells)
    clock = ti.field(ti.f64, 4)  # time, dt, max |a|^2, max c + |v|
    T, DT, ACC2, SIGNAL = range(4)
    n_ranges = 3 ** (dim - 1)

    @ti.func
    def cell_coords(P: ti.template(), gshape, xi):
        c = ti.cast(ti.floor((xi - P.grid_lo) * P.inv_cell), ti.i32)
        return ti.max(ti.min(c, gshape - 1), 0)

    @ti.func
    def linear(gshape, c):
        index = c[dim - 1]
        for k in ti.static(range(dim - 1)):
            index = index * gshape[dim - 2 - k] + c[dim - 2 - k]
        return index

    @ti.func
    def grid_shape():
        return ti.Vector([gshape_field[d] for d in ti.static(range(dim))])

    @ti.func
    def row_range(gshape, c, k):
        """Slots of the k-th row of 3 cells (x-1..x+1) around cell c; empty off the grid."""
        other = c
        inside = True
        for d in ti.static(range(1, dim)):
            other[d] = c[d] + (k // ti.static(3 ** (d - 1))) % 3 - 1
            if other[d] < 0 or other[d] >= gshape[d]:
                inside = False
        begin, end = 0, 0
        if inside:
            other[0] = ti.max(c[0] - 1, 0)
            first = linear(gshape, other)
            other[0] = ti.min(c[0] + 1, gshape[0] - 1)
            begin, end = start[first], start[linear(gshape, other) + 1]
        return begin, end

    @ti.func
    def tait(P: ti.template(), r):
        q = r / P.rho0
        q2 = q * q
        return P.B * (q2 * q2 * q2 * q - 1.0)

    @ti.kernel
    def sort(advance: ti.i32):
        ti.loop_config(serialize=True)
        for _ in range(1):
            P = load()
            dt = ti.min(P.courant * P.h / ti.max(clock[SIGNAL], 1e-30),
                        P.force_factor * ti.sqrt(P.h / ti.max(ti.sqrt(clock[ACC2]), 1e-30)))
            if advance == 0:  # the bootstrap: rates at t = 0
                dt = 0.0
            clock[DT] = dt
            clock[T] += dt
            clock[ACC2] = 0.0
            clock[SIGNAL] = 0.0
        dt = ti.cast(clock[DT], real)
        for i in range(n):
            P = load()
            gshape = grid_shape()
            xi = x[i]
            if kind[i] == FLUID:
                xi += dt * v[i] + 0.5 * dt * dt * a_prev[i]
            c = linear(gshape, cell_coords(P, gshape, xi))
            cell_of[i] = c
            ti.atomic_add(count[c], 1)
        ti.loop_config(serialize=True)
        for _ in range(1):
            running = 0
            for c in range(n_cells):
                start[c] = running
                fill[c] = running
                running += count[c]
                count[c] = 0
            start[n_cells] = running
        for i in range(n):
            P = load()
            slot = ti.atomic_add(fill[cell_of[i]], 1)
            kinds[slot] = kind[i]
            idss[slot] = ids[i]
            if kind[i] == FLUID:
                a = a_prev[i]
                xs[slot] = x[i] + dt * v[i] + 0.5 * dt * dt * a
                vs[slot] = v[i] + dt * a
                r = rho[i] + dt * drho_prev[i]
                rhos[slot] = r
                as_[slot] = a
                drhos[slot] = drho_prev[i]
                pr = tait(P, r)
                p[slot] = pr
                p_rho2[slot] = pr / (r * r)
            else:
                xs[slot] = x[i]
                vs[slot] = v[i]

    @ti.kernel
    def walls():
        for i in range(n):
            if kinds[i] == WALL:
                P = load()
                gshape = grid_shape()
                xi = xs[i]
                c = cell_coords(P, gshape, xi)
                s_w, s_pw = ti.cast(0.0, real), ti.cast(0.0, real)
                s_rw, s_vw = ti.Vector.zero(real, dim), ti.Vector.zero(real, dim)
                for k in range(n_ranges):
                    begin, end = row_range(gshape, c, k)
                    for j in range(begin, end):
                        rij = xi - xs[j]
                        r2 = rij.norm_sqr()
                        if r2 < P.support2 and kinds[j] == FLUID:
                            q = ti.sqrt(r2) / P.h
                            f = 0.25 * (2.0 - q) ** 3
                            if q < 1.0:
                                f = 1.0 - 1.5 * q * q + 0.75 * q * q * q
                            w = P.w_norm * f
                            s_w += w
                            s_pw += p[j] * w
                            s_rw += (rhos[j] * w) * rij
                            s_vw += w * vs[j]
                pw = ti.cast(0.0, real)
                ghost = vs[i]
                if s_w > 0.0:
                    pw = (s_pw + P.gravity.dot(s_rw)) / s_w
                    ghost = 2.0 * vs[i] - s_vw / s_w
                r = P.rho0 * ti.pow(ti.max(1.0 + pw / P.B, 0.05), 1.0 / P.gamma)
                rhos[i] = r
                pr = tait(P, r)
                p[i] = pr
                p_rho2[i] = pr / (r * r)
                vw[i] = ghost

    @ti.kernel
    def force():
        dt = ti.cast(clock[DT], real)
        for i in range(n):
            if kinds[i] == FLUID:
                P = load()
                gshape = grid_shape()
                h, c0, mass = P.h, P.c0, P.mass
                xi, vi, ri, pi = xs[i], vs[i], rhos[i], p_rho2[i]
                pri = p[i]
                c = cell_coords(P, gshape, xi)
                acc = ti.Vector.zero(real, dim)
                drho = ti.cast(0.0, real)
                for k in range(n_ranges):
                    begin, end = row_range(gshape, c, k)
                    for j in range(begin, end):
                        rij = xi - xs[j]
                        r2 = rij.norm_sqr()
                        if r2 < P.support2 and j != i:
                            r = ti.sqrt(r2)
                            q = r / h
                            gq = -0.75 * (2.0 - q) ** 2 / q
                            if q < 1.0:
                                gq = -3.0 + 2.25 * q
                            grad = (P.grad_norm * gq) * rij
                            fluid_j = kinds[j] == FLUID
                            vj = vs[j]
                            rj = rhos[j]
                            drho += mass * (vi - vj).dot(grad)  # continuity (walls: their own velocity)
                            acc -= mass * (pi + p_rho2[j]) * grad  # pressure
                            vav = vj if fluid_j else vw[j]  # viscosity: walls with the ghost velocity
                            vr = (vi - vav).dot(rij)
                            if vr < 0.0:
                                mu = h * vr / (r2 + 0.01 * h * h)
                                acc -= mass * (-P.alpha * c0 * mu / (0.5 * (ri + rj))) * grad
                            if fluid_j:  # density diffusion with the hydrostatic correction
                                rho_m = 0.5 * (ri + rj)
                                c2 = P.gamma * (0.5 * (pri + p[j]) + P.B) / rho_m
                                d = ri - rj - rho_m * P.gravity.dot(rij) / c2
                                drho += (2.0 * P.delta * h * c0 * d * rij.dot(grad) / (r2 + 0.01 * h * h)
                                         * mass / rj)
                acc += P.gravity
                # corrector
                x[i] = xi
                vn = vi + 0.5 * dt * (acc - as_[i])
                v[i] = vn
                a_prev[i] = acc
                rho[i] = ri + 0.5 * dt * (drho - drhos[i])
                drho_prev[i] = drho
                kind[i] = FLUID
                ids[i] = idss[i]
                a2 = ti.cast(acc.norm_sqr(), ti.f64)
                signal = ti.cast(c0 + vn.norm(), ti.f64)
                if a2 > clock[ACC2]:
                    ti.atomic_max(clock[ACC2], a2)
                if signal > clock[SIGNAL]:
                    ti.atomic_max(clock[SIGNAL], signal)
            else:
                x[i] = xs[i]
                v[i] = vs[i]
                kind[i] = WALL
                ids[i] = idss[i]

    class Reference:
        fluid = int(np.count_nonzero(scene.kind == FLUID))

        @staticmethod
        def step(k=1, advance=1):
            for _ in range(k):
                sort(advance)
                walls()
                force()

        @staticmethod
        def state():
            """(time, steps-free state in particle-id order: x, v, rho)."""
            order = np.argsort(ids.to_numpy())
            return clock.to_numpy()[T], x.to_numpy()[order], v.to_numpy()[order], rho.to_numpy()[order]

    x.from_numpy(scene.position if start_from is None else start_from.positions())
    v.from_numpy(scene.velocity if start_from is None else start_from.velocities())
    rho.from_numpy(scene.density if start_from is None else start_from.density())
    if start_from is not None and not np.all(start_from.kinds() == scene.kind):
        raise ValueError("the simulation has removed particles: the reference cannot start from it")
    kind.from_numpy(scene.kind)
    ids.from_numpy(np.arange(n, dtype=np.int32))
    clock.from_numpy(np.array([0.0 if start_from is None else start_from.time, 0.0, 0.0, 0.0]))
    Reference.step(1, advance=0)  # bootstrap as the engine does: rates and maxima at t = 0
    return Reference


def flagship(dim: int, dx: float):
    """The flagship dam break with its default physics, 2D or 3D."""
    import taisph

    case = taisph.cases.dam_break if dim == 2 else taisph.cases.dam_break_3d
    scene = case(dx=dx)
    assert {"dummy_walls", "density_diffusion"} <= set(scene.terms_by_name), "the reference's physics is not the default"
    return scene


def check(dim: int, dx: float, steps: int = 20) -> float:
    """Run the engine and the reference `steps` steps from the same particles; return the
    largest position difference over dx (round-off: the sums run in other orders)."""
    import taisph

    sim = taisph.Simulation(flagship(dim, dx))
    sim.step(steps)
    ref = setup(flagship(dim, dx))
    ref.step(steps)
    t, x, v, rho = ref.state()
    assert abs(t - sim.time) < 1e-9 * sim.time, (t, sim.time)
    return float(np.abs(x - sim.positions()).max() / dx)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m tools.benchmarks.bench_reference",
                                 description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2)
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--threads", type=int, default=None)
    ap.add_argument("--check", action="store_true", help="compare 20 steps with taisph's engine")
    args = ap.parse_args(argv)
    if args.check:
        import taisph

        taisph.engine.runtime.init(threads=args.threads)
        print(f"largest position difference after 20 steps: {check(args.dim, args.dx):.2e} dx")
        return
    kw = {} if args.threads is None else {"cpu_max_num_threads": args.threads}
    ti.init(arch=ti.cpu, default_fp=ti.f64, log_level=ti.WARN, **kw)
    ref = setup(flagship(args.dim, args.dx))
    ref.step(5)
    ti.sync()
    t0 = time.perf_counter()
    ref.step(args.steps)
    ti.sync()
    wall = time.perf_counter() - t0
    print(f"reference {args.dim}D dx={args.dx}: {ref.fluid} fluid, {args.steps} steps in {wall:.3f} s: "
          f"{ref.fluid * args.steps / wall / 1e6:.2f} M fluid particle-steps/s, "
          f"{wall / (ref.fluid * args.steps) * 1e9:.0f} ns per particle-step")


if __name__ == "__main__":
    main()
