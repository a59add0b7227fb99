"""Neighbour-loop levers measured on a bare force loop, outside taisph.

    python -m tools.benchmarks.bench_levers cells        # walk the 3 x 3 cells (edge >= support)
    python -m tools.benchmarks.bench_levers halfcell     # 5 x 5 cells of half the edge (fewer candidates)
    python -m tools.benchmarks.bench_levers verlet [f64|f32] [n_side] [skin]   # lists, skin a fraction of the support
    python -m tools.benchmarks.bench_levers symmetric    # each pair once, j's share by atomic adds

The loop of tools/benchmarks/bench_minimal.py (cubic spline gradient, pressure and continuity
sums; tools/benchmarks/bare_loop.py) over n_side^2 (default 141^2 = 19,881) cell-sorted particles
of a jittered lattice in a periodic unit box. "verlet" also prints the mean list length
and the cost of building the lists. Prints the best of 5 blocks of 100 calls.
docs/performance.md compares these with the same levers inside taisph.
"""
import sys

import taichi as ti

from tools.benchmarks.bare_loop import best_time, make_pair, sorted_lattice

variant = sys.argv[1]
prec = sys.argv[2] if len(sys.argv) > 2 else "f64"
n_side = int(sys.argv[3]) if len(sys.argv) > 3 else 141
real = ti.f64 if prec == "f64" else ti.f32
ti.init(arch=ti.cpu, default_fp=real)
dx = 1.0 / n_side
h = 1.3 * dx
support = 2 * h
sub = 2 if variant == "halfcell" else 1  # cells per support radius
G = int(sub / support)  # cells per side
cell = 1.0 / G
N = n_side * n_side
skin = float(sys.argv[4]) * support if len(sys.argv) > 4 else 0.1 * support
MAXN = 64
vec = ti.types.vector(2, real)
pair = make_pair(h, 2, real)

X, V, A = (ti.ndarray(vec, N) for _ in range(3))
R, D = ti.ndarray(real, N), ti.ndarray(real, N)
start = ti.ndarray(ti.i32, G * G + 1)
nlist = ti.ndarray(ti.i32, (N, MAXN))
ncount = ti.ndarray(ti.i32, N)
Vec1, Real1, I1 = ti.types.ndarray(vec, 1), ti.types.ndarray(real, 1), ti.types.ndarray(ti.i32, 1)
I2 = ti.types.ndarray(ti.i32, 2)


@ti.func
def cell_range(xi, oy, ox, start: ti.template()):
    """Slots of the cell at offset (ox, oy) from xi's cell, wrapping around the box."""
    ci = ti.cast(xi / cell, ti.i32)
    c = ((ci[1] + oy) % G) * G + (ci[0] + ox) % G
    return start[c], start[c + 1]


@ti.func
def separation(xi, xj):
    rij = xi - xj
    return rij - ti.round(rij)  # nearest image in the unit box


@ti.kernel
def cells(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, start: I1):
    for i in range(N):
        a = ti.Vector.zero(real, 2)
        d = ti.cast(0.0, real)
        for oy in range(-sub, sub + 1):
            for ox in range(-sub, sub + 1):
                begin, end = cell_range(X[i], oy, ox, start)
                for j in range(begin, end):
                    rij = separation(X[i], X[j])
                    r2 = rij.norm_sqr()
                    if r2 < support * support and j != i:
                        da, dd = pair(i, j, rij, r2, V, R)
                        a += da
                        d += dd
        A[i] = a
        D[i] = d


@ti.kernel
def symmetric(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, start: I1):
    """Each pair once (j > i): i's share summed locally, j's by atomic adds."""
    for i in range(N):
        A[i] = ti.Vector.zero(real, 2)
        D[i] = 0.0
    for i in range(N):
        a = ti.Vector.zero(real, 2)
        d = ti.cast(0.0, real)
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                begin, end = cell_range(X[i], oy, ox, start)
                for j in range(begin, end):
                    if j > i:
                        rij = separation(X[i], X[j])
                        r2 = rij.norm_sqr()
                        if r2 < support * support:
                            da, dd = pair(i, j, rij, r2, V, R)
                            a += da
                            d += dd
                            ti.atomic_sub(A[j], da)
                            ti.atomic_add(D[j], dd)
        ti.atomic_add(A[i], a)
        ti.atomic_add(D[i], d)


@ti.kernel
def build(X: Vec1, start: I1, nlist: I2, ncount: I1):
    reach2 = (support + skin) ** 2
    for i in range(N):
        k = 0
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                begin, end = cell_range(X[i], oy, ox, start)
                for j in range(begin, end):
                    if separation(X[i], X[j]).norm_sqr() < reach2 and j != i and k < MAXN:
                        nlist[i, k] = j
                        k += 1
        ncount[i] = k


@ti.kernel
def verlet(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, nlist: I2, ncount: I1):
    for i in range(N):
        a = ti.Vector.zero(real, 2)
        d = ti.cast(0.0, real)
        for k in range(ncount[i]):
            j = nlist[i, k]
            rij = separation(X[i], X[j])
            r2 = rij.norm_sqr()
            if r2 < support * support:
                da, dd = pair(i, j, rij, r2, V, R)
                a += da
                d += dd
        A[i] = a
        D[i] = d


pos, starts = sorted_lattice(n_side, 2, G, jitter=0.05)
X.from_numpy(pos)
R.fill(1000.0)
start.from_numpy(starts)
if variant == "verlet":
    build(X, start, nlist, ncount)
    print("mean list length", ncount.to_numpy().mean())
    print("build %.3f ms" % (best_time(lambda: build(X, start, nlist, ncount), 20, 1) * 1e3))
    f = lambda: verlet(X, V, R, A, D, nlist, ncount)
elif variant == "symmetric":
    f = lambda: symmetric(X, V, R, A, D, start)
else:
    f = lambda: cells(X, V, R, A, D, start)
best = best_time(f, 100)
print(variant, prec, N, "%.3f ms  %.1f ns/particle" % (best * 1e3, best / N * 1e9))
