"""Shared pieces of the bare-loop benchmarks (bench_minimal.py, bench_minimal_3d.py,
bench_levers.py; they import it as tools.benchmarks.bare_loop): a cell-sorted lattice
in a periodic unit box, the pair sums they all time (cubic spline gradient, pressure
and continuity only), and the timer.

Not part of taisph: these loops are the floor taisph's force pass is compared with in
docs/performance.md.
"""

import math
import time

import numpy as np
import taichi as ti

SIGMA_GRAD = {2: 10 / (7 * math.pi), 3: 1 / math.pi}  # cubic spline normalisation


def sorted_lattice(n_side: int, dim: int, cells_per_side: int, jitter: float = 0.0, seed: int = 1):
    """(positions sorted by cell, cell start slots): n_side^dim points of a lattice in
    the periodic unit box (jittered by `jitter` spacings), cells numbered x-fastest."""
    dx = 1.0 / n_side
    axis = (np.arange(n_side) + 0.5) * dx
    pos = np.stack(np.meshgrid(*[axis] * dim, indexing="ij"), -1).reshape(-1, dim)
    if jitter:
        pos += np.random.default_rng(seed).uniform(-jitter, jitter, pos.shape) * dx
        pos %= 1.0
    c = np.floor(pos * cells_per_side).astype(int) % cells_per_side
    cell_of = c[:, dim - 1]
    for d in range(dim - 2, -1, -1):
        cell_of = cell_of * cells_per_side + c[:, d]
    order = np.argsort(cell_of, kind="stable")
    starts = np.searchsorted(cell_of[order], np.arange(cells_per_side**dim + 1)).astype(np.int32)
    return pos[order], starts


def make_pair(h: float, dim: int, real=ti.f64):
    """A ti.func giving pair (i, j)'s shares (dv_i, drho_i): cubic spline gradient,
    symmetric pressure term with R = P/rho^2, continuity, particle mass 1e-4."""
    grad_norm = SIGMA_GRAD[dim] / h ** (dim + 2)

    @ti.func
    def pair(i, j, rij, r2, V: ti.template(), R: ti.template()):
        q = ti.sqrt(r2) / h
        g = ti.cast(0.0, real)
        if q < 1:
            g = -3 + 2.25 * q
        elif q < 2:
            g = -0.75 * (2 - q) ** 2 / q
        grad = grad_norm * g * rij
        return -0.0001 * (R[i] + R[j]) * grad, 0.0001 * (V[i] - V[j]).dot(grad)

    return pair


def best_time(call, calls: int, blocks: int = 5) -> float:
    """Seconds per call: the best of `blocks` blocks of `calls` calls, after a warm-up."""
    call()
    ti.sync()
    best = math.inf
    for _ in range(blocks):
        start = time.perf_counter()
        for _ in range(calls):
            call()
        ti.sync()
        best = min(best, (time.perf_counter() - start) / calls)
    return best
