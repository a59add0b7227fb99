"""Reference point: a minimal fused SPH force loop, outside taisph, on this machine.

    python -m tools.benchmarks.bench_minimal field     # Taichi fields
    python -m tools.benchmarks.bench_minimal nd        # Taichi ndarrays (what taisph uses)

One parallel loop over 141 x 141 = 19,881 particles pre-sorted by cell in a periodic
unit box: cubic spline gradient, pressure and continuity sums, per-particle P/rho^2
read from an array (no EOS, no sort, no integration, no walls, no viscosity). It is
the floor taisph's force pass is compared with in docs/performance.md: timings on a
shared VM drift by up to 2x during a day, so the ratio measured in the same minute
says more than either number alone. Prints the best of 5 blocks of 100 calls.
"""
import sys

import taichi as ti

from tools.benchmarks.bare_loop import best_time, make_pair, sorted_lattice

mode = sys.argv[1] if len(sys.argv) > 1 else "nd"
ti.init(arch=ti.cpu, default_fp=ti.f64)
n_side = 141
h = 1.3 / n_side
support = 2 * h
G = int(1.0 / support)  # cells per side
cell = 1.0 / G
N = n_side * n_side
vec = ti.types.vector(2, ti.f64)
pair = make_pair(h, 2)  # R stands for P/rho^2, precomputed per particle


@ti.func
def sums(X: ti.template(), V: ti.template(), R: ti.template(), A: ti.template(), D: ti.template(),
         start: ti.template()):
    for i in range(N):
        xi = X[i]
        ci = ti.cast(xi / cell, ti.i32)
        a = ti.Vector([0.0, 0.0])
        d = 0.0
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                c = ((ci[1] + oy) % G) * G + (ci[0] + ox) % G
                for j in range(start[c], start[c + 1]):
                    rij = xi - X[j]
                    rij -= ti.round(rij)  # periodic unit box
                    r2 = rij.norm_sqr()
                    if r2 < support * support and j != i:
                        da, dd = pair(i, j, rij, r2, V, R)
                        a += da
                        d += dd
        A[i] = a
        D[i] = d


if mode == "field":
    X, V, A = (ti.Vector.field(2, ti.f64, N) for _ in range(3))
    R, D = ti.field(ti.f64, N), ti.field(ti.f64, N)
    start = ti.field(ti.i32, G * G + 1)

    @ti.kernel
    def force_fields():
        sums(X, V, R, A, D, start)

    f = force_fields
else:
    X, V, A = (ti.ndarray(vec, N) for _ in range(3))
    R, D = ti.ndarray(ti.f64, N), ti.ndarray(ti.f64, N)
    start = ti.ndarray(ti.i32, G * G + 1)
    Vec1, Real1 = ti.types.ndarray(vec, 1), ti.types.ndarray(ti.f64, 1)

    @ti.kernel
    def force_ndarrays(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, start: ti.types.ndarray(ti.i32, 1)):
        sums(X, V, R, A, D, start)

    def f():
        force_ndarrays(X, V, R, A, D, start)

pos, starts = sorted_lattice(n_side, 2, G)  # the loop reads cell-sorted data
X.from_numpy(pos)
R.fill(1000.0)
start.from_numpy(starts)
best = best_time(f, 100)
print(mode, "%.3f ms  %.1f ns/particle" % (best * 1e3, best / N * 1e9))
