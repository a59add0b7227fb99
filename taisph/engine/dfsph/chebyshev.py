"""Chebyshev acceleration of the density solve's Jacobi iterations (the host's side).

A Jacobi iteration x' = J(x) whose error falls by a factor rho per iteration (the
spectral radius of its iteration matrix) is accelerated by the Chebyshev semi-iteration
(Golub & Van Loan, Matrix Computations, sec. 11.2.8; Wang 2015, "A Chebyshev
semi-iterative approach for accelerating projective and position-based dynamics",
ACM TOG 34(6) 246, for the same use with a projection):

    x_{k+1} = x_{k-1} + w_{k+1} (J(x_k) - x_{k-1}),
    w_1 = 1,  w_2 = 2 / (2 - rho^2),  w_{k+1} = 4 / (4 - rho^2 w_k),

then projected (a pressure is never below zero): the error of a long solve falls as
rho^(k/2) instead of rho^k. The device applies the weight (:mod:`.kernels`, the density
iteration, with the previous pressure ``kappa_prev``); this class chooses it from the
mean errors the host reads after each iteration anyway.

rho is not known in advance (it depends on the resolution, the fluid's extent and the
free surface): the first :data:`START` iterations are plain Jacobi, and rho is estimated
from the rate at which their error fell over the last three, r = (e_k / e_{k-3})^(1/3),
moved towards 1 by :data:`SAFETY` (rho = 1 - SAFETY (1 - r)): an estimate below the
true rho amplifies the slowest modes, one above it only accelerates less. A solve whose
error climbs above twice its best returns to plain Jacobi and estimates rho again.
Solves that converge within START iterations (most steps of a flow) are plain
Jacobi, bit for bit. START and SAFETY against the alternatives: docs/dfsph.md,
"Chebyshev acceleration".
"""

import math

START = 8  # plain Jacobi iterations before the first estimate of rho
SAFETY = 0.5  # rho = 1 - SAFETY (1 - r): halfway between the observed rate r and 1 (1: r itself)
DIVERGING = 2.0  # an error above this many times the solve's best: back to plain Jacobi


class Chebyshev:
    """The weights of one solve: :meth:`next` takes the error of the iteration just made and
    returns the weight of the next (1: plain Jacobi)."""

    def __init__(self):
        self.errors = []
        self.rho2 = None  # rho^2, once estimated
        self.weight = 1.0
        self.best = math.inf

    def next(self, error: float) -> float:
        if self.rho2 is None:
            self.errors.append(error)
            e = self.errors
            if len(e) < START or not e[-4] > 0.0:
                return 1.0
            rate = (e[-1] / e[-4]) ** (1.0 / 3.0)
            if not 0.0 < rate < 1.0:  # not falling (yet): stay plain
                return 1.0
            rho = 1.0 - SAFETY * (1.0 - rate)
            self.rho2 = rho * rho
            self.weight = 2.0 / (2.0 - self.rho2)
            self.best = error
            return self.weight
        if error > DIVERGING * self.best:
            self.rho2, self.errors, self.weight = None, [], 1.0
            return 1.0
        self.best = min(self.best, error)
        self.weight = 4.0 / (4.0 - self.rho2 * self.weight)
        return self.weight
