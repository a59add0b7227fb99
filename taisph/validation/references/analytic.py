"""Analytic and semi-analytic reference solutions of the validation cases (numpy).

Sources are given per function; the formulas are collected, with their conventions,
in ``docs/reference/FORMULAS.md``. Every function is vectorised over positions.
"""

from __future__ import annotations

import math

import numpy as np


# --- start-up channel flows, Morris, Fox & Zhu (1997) ------------------------------------
def poiseuille_startup(y, t, L, nu, F, terms=200):
    """Velocity u(y, t) of plane Poiseuille flow between no-slip walls at y = 0 and L,
    driven by a body force (acceleration) F switched on at t = 0 on fluid at rest
    (Morris et al. 1997 eq. 21):

        u = F/(2 nu) y (L - y) - sum_n 4 F L^2/(nu pi^3 (2n+1)^3) sin((2n+1) pi y/L) exp(-(2n+1)^2 pi^2 nu t/L^2)."""
    y = np.asarray(y, float)
    u = F / (2.0 * nu) * y * (L - y)
    for n in range(terms):
        k = 2 * n + 1
        u = u - 4.0 * F * L**2 / (nu * math.pi**3 * k**3) * np.sin(k * math.pi * y / L) * math.exp(
            -(k**2) * math.pi**2 * nu * t / L**2)
    return u


def couette_startup(y, t, L, nu, V0, terms=400):
    """Velocity u(y, t) of plane Couette flow: fluid at rest between walls at y = 0
    (fixed) and y = L, which starts moving at V0 at t = 0 (Morris et al. 1997 eq. 22):

        u = V0 y/L + sum_{n>=1} 2 V0 (-1)^n/(n pi) sin(n pi y/L) exp(-n^2 pi^2 nu t/L^2)."""
    y = np.asarray(y, float)
    u = V0 * y / L
    if t <= 0:
        return np.where(np.isclose(y, L), V0, 0.0)
    for n in range(1, terms + 1):
        decay = math.exp(-(n**2) * math.pi**2 * nu * t / L**2)
        if decay < 1e-16:
            break
        u = u + 2.0 * V0 * (-1) ** n / (n * math.pi) * np.sin(n * math.pi * y / L) * decay
    return u


# --- Taylor-Green vortex -------------------------------------------------------------------
def taylor_green(x, y, t, U=1.0, L=1.0, nu=0.01, rho=1.0):
    """The 2D Taylor-Green vortex in the periodic box [0, L]^2 (4 vortices; PySPH's
    ``examples/taylor_green.py`` convention), k = 2 pi/L:

        u = -U e^{-2 nu k^2 t} cos(kx) sin(ky),   v = U e^{-2 nu k^2 t} sin(kx) cos(ky),
        p = -rho U^2/4 e^{-4 nu k^2 t} (cos 2kx + cos 2ky).

    max |u| decays as exp(-8 pi^2 nu t / L^2). Returns (u, v, p)."""
    k = 2.0 * math.pi / L
    f = U * math.exp(-2.0 * nu * k * k * t)
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    u = -f * np.cos(k * x) * np.sin(k * y)
    v = f * np.sin(k * x) * np.cos(k * y)
    p = -0.25 * rho * f * f * (np.cos(2 * k * x) + np.cos(2 * k * y))
    return u, v, p


# --- elliptical drop -------------------------------------------------------------------------
def elliptical_drop(t, R=1.0, A0=100.0):
    """Semi-axes (a, b) and strain rate A of an inviscid drop, initially a circle of
    radius R with velocity u = -A0 x, v = A0 y (Monaghan 1994 sec. 5; the ODE as in
    PySPH ``examples/elliptical_drop.py``):

        da/dt = -a A,   dA/dt = A^2 (a^4 - R^4)/(a^4 + R^4),   a b = R^2.

    Integrated with classical RK4 on a fine step (error < 1e-9 at t = 0.0076)."""
    t = float(t)
    n = max(1, int(math.ceil(abs(t) * A0 * 2000)))
    h = t / n
    a, A = R, A0

    def rate(a, A):
        a4, r4 = a**4, R**4
        return -a * A, A * A * (a4 - r4) / (a4 + r4)

    for _ in range(n):
        k1 = rate(a, A)
        k2 = rate(a + 0.5 * h * k1[0], A + 0.5 * h * k1[1])
        k3 = rate(a + 0.5 * h * k2[0], A + 0.5 * h * k2[1])
        k4 = rate(a + h * k3[0], A + h * k3[1])
        a += h / 6.0 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        A += h / 6.0 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return a, R * R / a, A
