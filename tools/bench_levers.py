"""Neighbour-loop levers measured on a bare force loop, outside taisph.

    python tools/bench_levers.py cells        # walk the 3 x 3 cells (edge >= support)
    python tools/bench_levers.py halfcell     # 5 x 5 cells of half the edge (fewer candidates)
    python tools/bench_levers.py verlet [f64|f32] [n_side] [skin]   # lists, skin a fraction of the support
    python tools/bench_levers.py symmetric    # each pair once, j's share by atomic adds

The loop of tools/bench_minimal.py (cubic spline gradient, pressure and continuity
sums) over n_side^2 (default 141^2 = 19,881) cell-sorted particles of a jittered
lattice in a periodic unit box. "verlet" also prints the mean list length and the cost
of building the lists. Prints the best of 5 blocks of 100 calls. docs/performance.md
compares these with the same levers inside taisph.
"""
import math
import sys
import time

import numpy as np
import taichi as ti

variant = sys.argv[1]
prec = sys.argv[2] if len(sys.argv) > 2 else "f64"
n_side = int(sys.argv[3]) if len(sys.argv) > 3 else 141
real = ti.f64 if prec == "f64" else ti.f32
ti.init(arch=ti.cpu, default_fp=real)
dx = 1.0 / n_side
h = 1.3 * dx
support = 2 * h
sub = 2 if variant == "halfcell" else 1
G = int(sub / support)
cell = 1.0 / G
N = n_side * n_side
grad_norm = 10 / (7 * math.pi) / h**4
vec = ti.types.vector(2, real)
skin = float(sys.argv[4]) * support if len(sys.argv) > 4 else 0.1 * support
MAXN = 64

rng = np.random.default_rng(1)
axis = (np.arange(n_side) + 0.5) * dx
pos0 = np.stack(np.meshgrid(axis, axis, indexing="ij"), -1).reshape(-1, 2)
pos0 += rng.uniform(-0.05, 0.05, pos0.shape) * dx
pos0 %= 1.0
cell_of = (np.floor(pos0[:, 1] / cell).astype(int) % G) * G + (np.floor(pos0[:, 0] / cell).astype(int) % G)
order = np.argsort(cell_of, kind="stable")
starts = np.searchsorted(cell_of[order], np.arange(G * G + 1)).astype(np.int32)
R_ = 2 * sub + 1  # cells per axis visited

X, V, A = (ti.ndarray(vec, N) for _ in range(3))
R, D = ti.ndarray(real, N), ti.ndarray(real, N)
start = ti.ndarray(ti.i32, G * G + 1)
nlist = ti.ndarray(ti.i32, (N, MAXN))
ncount = ti.ndarray(ti.i32, N)
Vec1, Real1, I1 = ti.types.ndarray(vec, 1), ti.types.ndarray(real, 1), ti.types.ndarray(ti.i32, 1)
I2 = ti.types.ndarray(ti.i32, 2)


@ti.func
def pair(i, j, rij, r2, p_i, a: ti.template(), d: ti.template(), V: ti.template(), R: ti.template()):
    q = ti.sqrt(r2) / h
    g = ti.cast(0.0, real)
    if q < 1:
        g = -3 + 2.25 * q
    elif q < 2:
        g = -0.75 * (2 - q) ** 2 / q
    grad = grad_norm * g * rij
    a -= 0.0001 * (p_i + R[j]) * grad
    d += 0.0001 * (V[i] - V[j]).dot(grad)


@ti.kernel
def cells(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, start: I1):
    for i in range(N):
        xi = X[i]
        ci = ti.cast(xi / cell, ti.i32)
        a = ti.Vector([0.0, 0.0], real)
        d = ti.cast(0.0, real)
        p_i = R[i]
        for oy in range(-sub, sub + 1):
            for ox in range(-sub, sub + 1):
                c = ((ci[1] + oy) % G) * G + (ci[0] + ox) % G
                for j in range(start[c], start[c + 1]):
                    rij = xi - X[j]
                    rij -= ti.round(rij)
                    r2 = rij.norm_sqr()
                    if r2 < support * support and j != i:
                        pair(i, j, rij, r2, p_i, a, d, V, R)
        A[i] = a
        D[i] = d


@ti.kernel
def symmetric(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, start: I1):
    """Each pair once (j > i): i's share summed locally, j's by atomic adds."""
    for i in range(N):
        A[i] = ti.Vector([0.0, 0.0], real)
        D[i] = 0.0
    for i in range(N):
        xi = X[i]
        ci = ti.cast(xi / cell, ti.i32)
        a = ti.Vector([0.0, 0.0], real)
        d = ti.cast(0.0, real)
        p_i = R[i]
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                c = ((ci[1] + oy) % G) * G + (ci[0] + ox) % G
                for j in range(start[c], start[c + 1]):
                    if j > i:
                        rij = xi - X[j]
                        rij -= ti.round(rij)
                        r2 = rij.norm_sqr()
                        if r2 < support * support:
                            q = ti.sqrt(r2) / h
                            g = ti.cast(0.0, real)
                            if q < 1:
                                g = -3 + 2.25 * q
                            elif q < 2:
                                g = -0.75 * (2 - q) ** 2 / q
                            grad = grad_norm * g * rij
                            f = 0.0001 * (p_i + R[j]) * grad
                            dd = 0.0001 * (V[i] - V[j]).dot(grad)
                            a -= f
                            d += dd
                            ti.atomic_add(A[j], f)
                            ti.atomic_add(D[j], dd)
        ti.atomic_add(A[i], a)
        ti.atomic_add(D[i], d)


@ti.kernel
def build(X: Vec1, start: I1, nlist: I2, ncount: I1):
    rs = (support + skin) ** 2
    for i in range(N):
        xi = X[i]
        ci = ti.cast(xi / cell, ti.i32)
        k = 0
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                c = ((ci[1] + oy) % G) * G + (ci[0] + ox) % G
                for j in range(start[c], start[c + 1]):
                    rij = xi - X[j]
                    rij -= ti.round(rij)
                    if rij.norm_sqr() < rs and j != i and k < MAXN:
                        nlist[i, k] = j
                        k += 1
        ncount[i] = k


@ti.kernel
def verlet(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, nlist: I2, ncount: I1):
    for i in range(N):
        xi = X[i]
        a = ti.Vector([0.0, 0.0], real)
        d = ti.cast(0.0, real)
        p_i = R[i]
        for k in range(ncount[i]):
            j = nlist[i, k]
            rij = xi - X[j]
            rij -= ti.round(rij)
            r2 = rij.norm_sqr()
            if r2 < support * support:
                pair(i, j, rij, r2, p_i, a, d, V, R)
        A[i] = a
        D[i] = d


X.from_numpy(pos0[order])
R.fill(1000.0)
start.from_numpy(starts)
if variant == "verlet":
    build(X, start, nlist, ncount)
    f = lambda: verlet(X, V, R, A, D, nlist, ncount)
    ti.sync()
    print("mean list length", ncount.to_numpy().mean())
    t = time.perf_counter()
    for _ in range(20):
        build(X, start, nlist, ncount)
    ti.sync()
    print("build %.3f ms" % ((time.perf_counter() - t) / 20 * 1e3))
elif variant == "symmetric":
    f = lambda: symmetric(X, V, R, A, D, start)
else:
    f = lambda: cells(X, V, R, A, D, start)
f()
ti.sync()
best = math.inf
for _ in range(5):
    t = time.perf_counter()
    for _ in range(100):
        f()
    ti.sync()
    best = min(best, (time.perf_counter() - t) / 100)
print(variant, prec, N, "%.3f ms  %.1f ns/particle" % (best * 1e3, best / N * 1e9))
