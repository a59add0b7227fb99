"""Smoothing kernels W(r, h).

Every kernel is written as ``W(r, h) = sigma_d / h^d * f(q)`` with ``q = r / h`` and a
support radius ``support * h``. Its gradient with respect to the first particle is

    grad_i W_ij = sigma_d / h^(d+2) * g(q) * r_ij,     g(q) = f'(q) / q,

and every ``g`` below is finite at ``q = 0``, so coincident particles never divide by
zero. ``sigma_d`` normalises the kernel in 1, 2 and 3 dimensions; the tests integrate
each kernel numerically and check it against 1. Each kernel also has ``f_numpy``, its
``f`` on numpy arrays, for sums on the host (next to ``f``: one formula, two languages).
"""


import math

import numpy as np
import taichi as ti

from ..scene.names import KERNELS as NAMES  # the one list of the names (checked below)


class _Kernel:
    """What every kernel shares: its dimension and the evaluation with a smoothing
    length known only at run time (per particle, for a variable smoothing length;
    constant-h code uses the precomputed norms of the solver's parameter table)."""

    def __init__(self, dim: int = 2):
        self.dim = dim

    @ti.func
    def _inv_h_power(self, h, n: ti.template()):
        inv = 1.0 / h
        p = inv
        for _ in ti.static(range(n - 1)):
            p *= inv
        return p

    @ti.func
    def w_h(self, r, h):
        """W(r, h) = sigma_d / h^d f(r / h)."""
        return ti.static(self.sigma(self.dim)) * self._inv_h_power(h, self.dim) * self.f(r / h)

    @ti.func
    def grad_factor_h(self, r, h):
        """F with grad_i W(r_ij, h) = F r_ij: sigma_d / h^(d+2) g(r / h)."""
        return ti.static(self.sigma(self.dim)) * self._inv_h_power(h, self.dim + 2) * self.g(r / h)


@ti.data_oriented
class CubicSpline(_Kernel):
    """M4 cubic spline, Monaghan & Lattanzio (1985), as in Monaghan (1992) eq. 2.6.

    f(q) = 1 - 3/2 q^2 + 3/4 q^3   (0 <= q < 1)
           1/4 (2 - q)^3           (1 <= q < 2),   support 2h.
    """

    name = "spline"
    support = 2.0
    _sigma = {1: 2.0 / 3.0, 2: 10.0 / (7.0 * math.pi), 3: 1.0 / math.pi}

    def sigma(self, dim: int) -> float:
        return self._sigma[dim]

    @ti.func
    def f(self, q):
        result = 0.0
        if q < 1.0:
            result = 1.0 - 1.5 * q * q + 0.75 * q * q * q
        elif q < 2.0:
            t = 2.0 - q
            result = 0.25 * t * t * t
        return result

    def f_numpy(self, q):
        return np.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0))

    @ti.func
    def g(self, q):
        result = 0.0
        if q < 1.0:
            result = -3.0 + 2.25 * q
        elif q < 2.0:
            t = 2.0 - q
            result = -0.75 * t * t / q
        return result


@ti.data_oriented
class WendlandC2(_Kernel):
    """Wendland (1995) C2 kernel, in the q in [0, 2] form of Dehnen & Aly (2012).

    2D/3D: f(q) = (1 - q/2)^4 (2q + 1),  sigma_2 = 7/(4 pi), sigma_3 = 21/(16 pi).
    1D:    f(q) = (1 - q/2)^3 (3q/2 + 1), sigma_1 = 5/8.          Support 2h.
    """

    name = "wendland"
    support = 2.0
    _sigma = {1: 5.0 / 8.0, 2: 7.0 / (4.0 * math.pi), 3: 21.0 / (16.0 * math.pi)}

    def __init__(self, dim: int = 2):
        super().__init__(dim)
        self.one_d = dim == 1

    def sigma(self, dim: int) -> float:
        return self._sigma[dim]

    @ti.func
    def f(self, q):
        result = 0.0
        if q < 2.0:
            t = 1.0 - 0.5 * q
            if ti.static(self.one_d):
                result = t * t * t * (1.5 * q + 1.0)
            else:
                result = t * t * t * t * (2.0 * q + 1.0)
        return result

    def f_numpy(self, q):
        return np.where(q < 2, (1 - q / 2) ** 3 * ((1.5 * q + 1) if self.one_d else (1 - q / 2) * (2 * q + 1)), 0.0)

    @ti.func
    def g(self, q):
        result = 0.0
        if q < 2.0:
            t = 1.0 - 0.5 * q
            if ti.static(self.one_d):
                result = -3.0 * t * t
            else:
                result = -5.0 * t * t * t
        return result


def _gaussian_integral(dim: int, cut: float) -> float:
    """Integral over the ball q < cut of exp(-q^2) - exp(-cut^2) in `dim` dimensions."""
    e = math.exp(-cut * cut)
    if dim == 1:
        return math.sqrt(math.pi) * math.erf(cut) - 2.0 * cut * e
    if dim == 2:
        return math.pi * (1.0 - e) - math.pi * cut * cut * e
    # 4 pi [ int_0^c q^2 exp(-q^2) dq - c^3/3 e ]
    inner = math.sqrt(math.pi) / 4.0 * math.erf(cut) - 0.5 * cut * e
    return 4.0 * math.pi * (inner - cut**3 / 3.0 * e)


@ti.data_oriented
class Gaussian(_Kernel):
    """Gaussian kernel truncated at q = 3 and renormalised (Monaghan 1992, eq. 2.5).

    f(q) = exp(-q^2) - exp(-9) for q < 3, so W is continuous at the cut-off;
    sigma_d = 1 / integral of f over the ball q < 3 (computed exactly, erf form),
    i.e. 0.04 %, 0.12 %, 0.30 % (1D, 2D, 3D) above the untruncated 1/pi^(d/2).
    """

    name = "gaussian"
    support = 3.0

    def sigma(self, dim: int) -> float:
        return 1.0 / _gaussian_integral(dim, self.support)

    @ti.func
    def f(self, q):
        result = 0.0
        if q < 3.0:
            result = ti.exp(-q * q) - ti.static(math.exp(-9.0))
        return result

    def f_numpy(self, q):
        return np.where(q < 3, np.exp(-q * q) - np.exp(-9.0), 0.0)

    @ti.func
    def g(self, q):
        result = 0.0
        if q < 3.0:
            result = -2.0 * ti.exp(-q * q)
        return result


KERNELS = {"spline": CubicSpline, "gaussian": Gaussian, "wendland": WendlandC2}
if tuple(KERNELS) != NAMES:  # taisph/scene/names.py, in the same order
    raise ImportError(f"engine kernels {tuple(KERNELS)} differ from taisph.scene.names.KERNELS")


def make(name: str, dim: int):
    """The smoothing kernel called `name` ('spline', 'gaussian', 'wendland')."""
    try:
        cls = KERNELS[name]
    except KeyError:
        raise ValueError(f"unknown kernel {name!r}; choose one of {', '.join(KERNELS)}") from None
    return cls(dim)


def lattice_sum(name: str, dim: int, h: float, dx: float) -> float:
    """sum_j W(x_i - x_j) dx^dim over a cubic lattice of spacing dx, i included: the
    density sum_j m_j W_ij of a particle inside a lattice of particles of mass rho dx^dim,
    over rho (1 for an exact quadrature; 1.0105 for Wendland C2 with h = 1.3 dx in 2D,
    0.99995 for the cubic spline)."""
    kernel, grid = _lattice(name, dim, h, dx)
    q = np.linalg.norm(grid, axis=1) / h
    return float(kernel.sigma(dim) / h**dim * kernel.f_numpy(q).sum() * dx**dim)


def _lattice(name: str, dim: int, h: float, dx: float):
    """The kernel and the points of a cubic lattice of spacing dx around the origin that
    its support reaches (the origin included)."""
    kernel = make(name, dim)
    reach = int(np.ceil(kernel.support * h / dx))
    axis = np.arange(-reach, reach + 1) * dx
    return kernel, np.stack(np.meshgrid(*([axis] * dim), indexing="ij"), -1).reshape(-1, dim)


def lattice_moment(name: str, dim: int, h: float, dx: float) -> float:
    """B = -sum_j dx^dim (x_i - x_j)_x (grad_i W_ij)_x over a cubic lattice of spacing dx:
    the factor by which the SPH gradient sum_j V_j (f_j - f_i) grad_i W_ij overstates the
    gradient of a linear field f on that lattice (1 for an exact quadrature; the same
    along every axis). 1.0105 for the cubic spline with h = 1.3 dx in 2D, 1.0010 with
    h = 1.25 dx, 0.9908 with 1.2 dx; Wendland C2 with h = 2 dx: 0.9992. The derivative of
    the kernel's shape is taken by central differences (error ~1e-10)."""
    kernel, grid = _lattice(name, dim, h, dx)
    r = np.linalg.norm(grid, axis=1)
    grid, r = grid[r > 0], r[r > 0]
    q, dq = r / h, 1e-6
    slope = (kernel.f_numpy(q + dq) - kernel.f_numpy(q - dq)) / (2 * dq)  # df/dq
    dw_dr = kernel.sigma(dim) / h ** (dim + 1) * slope
    return float(-np.sum(dw_dr * grid[:, 0] ** 2 / r) * dx**dim)


_evaluators: dict = {}


def _clear():
    _evaluators.clear()


def evaluate(name: str, dim: int, rij, h: float):
    """W and grad_i W for separation vectors ``rij`` (shape (M, dim), r_i - r_j),
    computed by the same Taichi functions the solver uses (for tests and tools)."""
    from . import runtime

    rt = runtime.current()
    runtime.on_reset(_clear)
    key = (rt, name, dim)
    if key not in _evaluators:
        kern = make(name, dim)
        sigma = kern.sigma(dim)
        real = rt.real
        vec = ti.types.vector(dim, real)

        @ti.kernel
        def tabulate(r: ti.types.ndarray(dtype=vec, ndim=1), w: ti.types.ndarray(dtype=real, ndim=1),
                     grad: ti.types.ndarray(dtype=vec, ndim=1), h: real):
            for k in range(r.shape[0]):
                q = r[k].norm() / h
                w[k] = sigma / h**dim * kern.f(q)
                grad[k] = sigma / h ** (dim + 2) * kern.g(q) * r[k]

        _evaluators[key] = (tabulate, vec, real)
    tabulate, vec, real = _evaluators[key]
    rij = np.ascontiguousarray(np.asarray(rij, dtype=rt.numpy_real).reshape(-1, dim))
    m = len(rij)
    r_nd, w_nd, g_nd = ti.ndarray(vec, m), ti.ndarray(real, m), ti.ndarray(vec, m)
    r_nd.from_numpy(rij)
    tabulate(r_nd, w_nd, g_nd, h)
    w, grad = w_nd.to_numpy().astype(float), g_nd.to_numpy().astype(float)
    runtime.free_ndarray(r_nd)
    runtime.free_ndarray(g_nd)
    return w, grad
