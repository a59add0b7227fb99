"""The Sedov-Taylor point explosion: the self-similar strong blast wave of energy E
released at a point (line, plane) in a gas of density rho0 at zero pressure, the
reference of the ``sedov`` case.

    R(t) = xi0 (E t^2 / rho0)^(1 / (nu + 2)),      nu = 1, 2, 3 (planar, cylindrical,
                                                   spherical), i.e. (E t^2/rho0)^(1/4) in 2D.

Behind the shock, u = R' f(eta), rho = rho0 g(eta), p = rho0 R'^2 P(eta) with
eta = r / R and R' = dR/dt = 2 R / ((nu + 2) t). Substituting into the Euler equations
(continuity, momentum, and entropy p rho^-gamma constant along paths) gives, with
a = f - eta,

    g f' + a g'                 = -(nu - 1) g f / eta
    a f' + P' / g               = (nu / 2) f
    -gamma a g' / g + a P' / P  = nu

integrated here (4th-order Runge-Kutta, 4000 steps) inward from the strong-shock
Rankine-Hugoniot values at eta = 1, f = P = 2 / (gamma + 1), g = (gamma + 1) / (gamma - 1).
The constant xi0 follows from the energy, E = sigma_nu rho0 R'^2 R^nu
int_0^1 (g f^2 / 2 + P / (gamma - 1)) eta^(nu-1) d eta, sigma = 2, 2 pi, 4 pi.
This reproduces the classical xi0 = 1.033 (gamma = 1.4) and 1.152 (gamma = 5/3) of the
spherical blast (Taylor 1950; Sedov 1959); tests/test_gas.py checks both.
"""

from __future__ import annotations

import math

import numpy as np

SIGMA = {1: 2.0, 2: 2.0 * math.pi, 3: 4.0 * math.pi}


class SedovTaylor:
    """Similarity solution for ratio of specific heats ``gamma`` in ``nu`` dimensions.

    ``xi0``; :meth:`radius` (shock radius at t); :meth:`sample` (rho, u, p at radii r).
    """

    def __init__(self, gamma: float = 1.4, nu: int = 2, steps: int = 4000, eta_min: float = 1e-4):
        if nu not in SIGMA:
            raise ValueError(f"nu must be 1, 2 or 3, got {nu!r}")
        self.gamma, self.nu = float(gamma), nu
        g = self.gamma
        y = np.array([2.0 / (g + 1.0), (g + 1.0) / (g - 1.0), 2.0 / (g + 1.0)])  # f, g, P at eta = 1
        eta = np.linspace(1.0, eta_min, steps + 1)
        d = eta[1] - eta[0]
        ys = [y]
        for e in eta[:-1]:
            k1 = self._rates(e, y)
            k2 = self._rates(e + d / 2, y + d / 2 * k1)
            k3 = self._rates(e + d / 2, y + d / 2 * k2)
            k4 = self._rates(e + d, y + d * k3)
            y = y + d / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            ys.append(y)
        ys = np.array(ys)
        self.eta = eta[::-1]
        self.f, self.g, self.P = (ys[::-1, k] for k in range(3))
        integrand = (0.5 * self.g * self.f**2 + self.P / (g - 1.0)) * self.eta ** (nu - 1)
        delta = 2.0 / (nu + 2.0)
        self.energy_integral = float(np.trapezoid(integrand, self.eta))
        self.xi0 = (delta**2 * SIGMA[nu] * self.energy_integral) ** (-1.0 / (nu + 2.0))

    def _rates(self, eta, y):
        """(f', g', P') from the three equations above, solved for f' first."""
        f, g, P = y
        nu, gam = self.nu, self.gamma
        a = f - eta
        df = (nu - gam * (nu - 1) * f / eta - 0.5 * nu * a * g * f / P) / (gam - a * a * g / P)
        dg = -g * ((nu - 1) * f / eta + df) / a
        dP = g * (0.5 * nu * f - a * df)
        return np.array([df, dg, dP])

    def radius(self, t, energy: float = 1.0, rho0: float = 1.0):
        """Shock radius R(t) = xi0 (E t^2 / rho0)^(1 / (nu + 2))."""
        return self.xi0 * (energy * np.asarray(t, dtype=float) ** 2 / rho0) ** (1.0 / (self.nu + 2.0))

    def sample(self, r, t: float, energy: float = 1.0, rho0: float = 1.0, p0: float = 0.0):
        """Density, radial velocity and pressure at radii r at time t (ambient gas at
        rest, density rho0 and pressure p0 outside the shock)."""
        R = float(self.radius(t, energy, rho0))
        speed = 2.0 / (self.nu + 2.0) * R / t
        eta = np.asarray(r, dtype=float) / R
        inside = eta < 1.0
        e = np.clip(eta, self.eta[0], 1.0)
        rho = np.where(inside, rho0 * np.interp(e, self.eta, self.g), rho0)
        u = np.where(inside, speed * np.interp(e, self.eta, self.f), 0.0)
        p = np.where(inside, rho0 * speed**2 * np.interp(e, self.eta, self.P), p0)
        return rho, u, p
