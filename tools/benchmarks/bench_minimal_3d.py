"""The bare force loop of tools/benchmarks/bench_minimal.py in 3D, for scale.

    python -m tools.benchmarks.bench_minimal_3d

32^3 = 32,768 particles of a lattice in a periodic unit box, cubic spline with
h = 1.3 dx, 27 cells per particle, pressure and continuity sums only
(tools/benchmarks/bare_loop.py). Prints the mean number of neighbours and the cost per particle
and per neighbour pair (best of 5 blocks of 10 calls): what one neighbour costs on
this machine before any physics.
"""
import taichi as ti

from tools.benchmarks.bare_loop import best_time, make_pair, sorted_lattice

ti.init(arch=ti.cpu, default_fp=ti.f64)
n_side = 32
h = 1.3 / n_side
support = 2 * h
G = int(1.0 / support)  # cells per side
cell = 1.0 / G
N = n_side**3
vec = ti.types.vector(3, ti.f64)
pair = make_pair(h, 3)
X, V, A = (ti.ndarray(vec, N) for _ in range(3))
R, D = ti.ndarray(ti.f64, N), ti.ndarray(ti.f64, N)
start = ti.ndarray(ti.i32, G**3 + 1)
npairs = ti.ndarray(ti.i32, N)
Vec1, Real1, I1 = ti.types.ndarray(vec, 1), ti.types.ndarray(ti.f64, 1), ti.types.ndarray(ti.i32, 1)


@ti.kernel
def force(X: Vec1, V: Vec1, R: Real1, A: Vec1, D: Real1, start: I1, npairs: I1):
    for i in range(N):
        xi = X[i]
        c0 = ti.cast(xi / cell, ti.i32)
        a = ti.Vector.zero(ti.f64, 3)
        d = 0.0
        k = 0
        for oz in range(-1, 2):
            for oy in range(-1, 2):
                for ox in range(-1, 2):
                    c = (((c0[2] + oz) % G) * G + (c0[1] + oy) % G) * G + (c0[0] + ox) % G
                    for j in range(start[c], start[c + 1]):
                        rij = xi - X[j]
                        rij -= ti.round(rij)  # nearest image in the unit box
                        r2 = rij.norm_sqr()
                        if r2 < support * support and j != i:
                            da, dd = pair(i, j, rij, r2, V, R)
                            a += da
                            d += dd
                            k += 1
        A[i] = a
        D[i] = d
        npairs[i] = k


pos, starts = sorted_lattice(n_side, 3, G)
X.from_numpy(pos)
R.fill(1000.0)
start.from_numpy(starts)
best = best_time(lambda: force(X, V, R, A, D, start, npairs), 10)
per_particle = npairs.to_numpy().mean()
print(f"3D bare N {N} pairs/particle {per_particle:.1f} {best * 1e3:.2f} ms {best / N * 1e9:.0f} ns/particle "
      f"{best / N / per_particle * 1e9:.1f} ns/pair")
