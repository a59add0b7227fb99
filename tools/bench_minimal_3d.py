"""The bare force loop of tools/bench_minimal.py in 3D, for scale.

    python tools/bench_minimal_3d.py

32^3 = 32,768 particles of a lattice in a periodic unit box, cubic spline with
h = 1.3 dx, 27 cells per particle, pressure and continuity sums only. Prints the mean
number of neighbours and the cost per particle and per neighbour pair (best of 5
blocks of 10 calls): what one neighbour costs on this machine before any physics.
"""
import math, sys, time
import numpy as np, taichi as ti
ti.init(arch=ti.cpu, default_fp=ti.f64)
n_side = 32; dx = 1.0 / n_side; h = 1.3 * dx; support = 2 * h
G = int(1.0 / support); cell = 1.0 / G; N = n_side**3
grad_norm = 1 / math.pi / h**5
vec = ti.types.vector(3, ti.f64)
axis = (np.arange(n_side) + 0.5) * dx
pos0 = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)
ci = np.floor(pos0 / cell).astype(int) % G
cell_of = (ci[:, 2] * G + ci[:, 1]) * G + ci[:, 0]
order = np.argsort(cell_of, kind="stable")
starts = np.searchsorted(cell_of[order], np.arange(G**3 + 1)).astype(np.int32)
X, V, A = (ti.ndarray(vec, N) for _ in range(3))
R, D = ti.ndarray(ti.f64, N), ti.ndarray(ti.f64, N)
start = ti.ndarray(ti.i32, G**3 + 1)
npairs = ti.ndarray(ti.i32, N)
@ti.kernel
def force(X: ti.types.ndarray(vec, 1), V: ti.types.ndarray(vec, 1), R: ti.types.ndarray(ti.f64, 1), A: ti.types.ndarray(vec, 1), D: ti.types.ndarray(ti.f64, 1), start: ti.types.ndarray(ti.i32, 1), npairs: ti.types.ndarray(ti.i32, 1)):
    for i in range(N):
        xi = X[i]
        c0 = ti.cast(xi / cell, ti.i32)
        a = ti.Vector([0.0, 0.0, 0.0]); d = 0.0; p_i = R[i]; k = 0
        for oz in range(-1, 2):
            for oy in range(-1, 2):
                for ox in range(-1, 2):
                    c = (((c0[2] + oz) % G) * G + (c0[1] + oy) % G) * G + (c0[0] + ox) % G
                    for j in range(start[c], start[c + 1]):
                        rij = xi - X[j]
                        rij -= ti.round(rij)
                        r2 = rij.norm_sqr()
                        if r2 < support * support and j != i:
                            q = ti.sqrt(r2) / h
                            g = 0.0
                            if q < 1:
                                g = -3 + 2.25 * q
                            elif q < 2:
                                g = -0.75 * (2 - q) ** 2 / q
                            grad = grad_norm * g * rij
                            a -= 0.0001 * (p_i + R[j]) * grad
                            d += 0.0001 * (V[i] - V[j]).dot(grad)
                            k += 1
        A[i] = a; D[i] = d; npairs[i] = k
X.from_numpy(pos0[order]); R.fill(1000.0); start.from_numpy(starts)
force(X, V, R, A, D, start, npairs); ti.sync()
best = 1e9
for _ in range(5):
    t = time.perf_counter()
    for _ in range(10): force(X, V, R, A, D, start, npairs)
    ti.sync(); best = min(best, (time.perf_counter() - t) / 10)
np_ = npairs.to_numpy().mean()
print(f"3D bare N {N} pairs/particle {np_:.1f} {best*1e3:.2f} ms {best/N*1e9:.0f} ns/particle {best/N/np_*1e9:.1f} ns/pair")
