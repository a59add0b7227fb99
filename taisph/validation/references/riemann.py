"""Exact solution of the Riemann problem of the 1D Euler equations for an ideal gas
(Toro 2009, *Riemann Solvers and Numerical Methods for Fluid Dynamics*, ch. 4), the
reference of the Sod shock tube (``cases/sod.py``).

    >>> sod = RiemannProblem((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), gamma=1.4)
    >>> round(sod.p_star, 5), round(sod.u_star, 5)
    (0.30313, 0.92745)
    >>> rho, u, p, e = sod.sample(x, t=0.2, x0=0.5)         # doctest: +SKIP

The star pressure p* solves f_L(p) + f_R(p) + (u_R - u_L) = 0 (Toro eq. 4.5), with
f_K the shock (Rankine-Hugoniot) branch for p > p_K and the rarefaction (isentropic)
branch otherwise (eqs. 4.6-4.7), by Newton iteration from the two-rarefaction guess
(eq. 4.46) to relative change 1e-14. The self-similar solution is then sampled at
S = (x - x0) / t (sec. 4.5). Works for any pair of states (left or right shocks and
rarefactions) that does not create a vacuum.
"""

from __future__ import annotations

import math

import numpy as np


class RiemannProblem:
    """Left and right states ``(rho, u, p)`` of an ideal gas with ratio of specific heats
    ``gamma``. Attributes: ``p_star``, ``u_star``, ``rho_star_left``, ``rho_star_right``
    and the wave speeds ``speeds`` (dict: left head/tail or shock, contact, right ...)."""

    def __init__(self, left, right, gamma: float = 1.4):
        self.gamma = g = float(gamma)
        self.left = tuple(float(v) for v in left)
        self.right = tuple(float(v) for v in right)
        (rl, ul, pl), (rr, ur, pr) = self.left, self.right
        if min(rl, pl, rr, pr) <= 0:
            raise ValueError("densities and pressures must be positive")
        self.cl, self.cr = math.sqrt(g * pl / rl), math.sqrt(g * pr / rr)
        if 2.0 / (g - 1.0) * (self.cl + self.cr) <= ur - ul:
            raise ValueError("these states generate a vacuum (Toro eq. 4.40); not supported")
        self.p_star = p = self._solve_pressure()
        fl, _ = self._f(p, rl, pl, self.cl)
        fr, _ = self._f(p, rr, pr, self.cr)
        self.u_star = 0.5 * (ul + ur) + 0.5 * (fr - fl)
        self.rho_star_left = self._rho_star(p, rl, pl)
        self.rho_star_right = self._rho_star(p, rr, pr)
        self.speeds = self._speeds()

    # --- p* ---------------------------------------------------------------------
    def _f(self, p, rho_k, p_k, c_k):
        """f_K(p) and its derivative (Toro eqs. 4.6, 4.7, 4.37)."""
        g = self.gamma
        if p > p_k:  # shock
            a = 2.0 / ((g + 1.0) * rho_k)
            b = (g - 1.0) / (g + 1.0) * p_k
            root = math.sqrt(a / (p + b))
            return (p - p_k) * root, root * (1.0 - 0.5 * (p - p_k) / (b + p))
        ratio = p / p_k  # rarefaction
        f = 2.0 * c_k / (g - 1.0) * (ratio ** ((g - 1.0) / (2.0 * g)) - 1.0)
        return f, ratio ** (-(g + 1.0) / (2.0 * g)) / (rho_k * c_k)

    def _solve_pressure(self):
        g = self.gamma
        (rl, ul, pl), (rr, ur, pr) = self.left, self.right
        z = (g - 1.0) / (2.0 * g)
        # two-rarefaction approximation as the initial guess (Toro eq. 4.46)
        p = ((self.cl + self.cr - 0.5 * (g - 1.0) * (ur - ul)) / (self.cl / pl**z + self.cr / pr**z)) ** (1.0 / z)
        for _ in range(100):
            fl, dl = self._f(p, rl, pl, self.cl)
            fr, dr = self._f(p, rr, pr, self.cr)
            new = max(p - (fl + fr + ur - ul) / (dl + dr), 1e-12 * p)
            change = abs(new - p) / (0.5 * (new + p))
            p = new
            if change < 1e-14:
                return p
        raise RuntimeError("Newton iteration for p* did not converge")

    def _rho_star(self, p, rho_k, p_k):
        g = self.gamma
        ratio = p / p_k
        if p > p_k:  # behind a shock (Toro eqs. 4.50, 4.57)
            k = (g - 1.0) / (g + 1.0)
            return rho_k * (ratio + k) / (ratio * k + 1.0)
        return rho_k * ratio ** (1.0 / g)  # isentropic (eqs. 4.53, 4.60)

    def _shock_speed(self, rho_k, u_k, p_k, c_k, side):
        g = self.gamma
        root = math.sqrt((g + 1.0) / (2.0 * g) * self.p_star / p_k + (g - 1.0) / (2.0 * g))
        return u_k - c_k * root if side < 0 else u_k + c_k * root  # Toro eqs. 4.52, 4.59

    def _speeds(self) -> dict:
        (rl, ul, pl), (rr, ur, pr) = self.left, self.right
        g = self.gamma
        s = {"contact": self.u_star}
        if self.p_star > pl:
            s["left_shock"] = self._shock_speed(rl, ul, pl, self.cl, -1)
        else:
            c_star = self.cl * (self.p_star / pl) ** ((g - 1.0) / (2.0 * g))
            s["left_head"], s["left_tail"] = ul - self.cl, self.u_star - c_star
        if self.p_star > pr:
            s["right_shock"] = self._shock_speed(rr, ur, pr, self.cr, +1)
        else:
            c_star = self.cr * (self.p_star / pr) ** ((g - 1.0) / (2.0 * g))
            s["right_tail"], s["right_head"] = self.u_star + c_star, ur + self.cr
        return s

    # --- sampling ---------------------------------------------------------------------
    def sample(self, x, t: float, x0: float = 0.0):
        """Density, velocity, pressure and specific internal energy at positions x
        (numpy arrays) at time t > 0, the initial discontinuity at x0."""
        if t <= 0:
            raise ValueError("sample at t > 0")
        g = self.gamma
        S = (np.asarray(x, dtype=float) - x0) / t
        rho, u, p = (np.empty_like(S) for _ in range(3))
        for side, state, c, sign in ((-1, self.left, self.cl, 1.0), (+1, self.right, self.cr, -1.0)):
            rk, uk, pk = state
            here = S < self.u_star if side < 0 else S >= self.u_star
            rho_star = self.rho_star_left if side < 0 else self.rho_star_right
            name = "left" if side < 0 else "right"
            if self.p_star > pk:  # shock: unshocked state beyond it, star state behind
                beyond = here & ((S < self.speeds[f"{name}_shock"]) if side < 0 else (S > self.speeds[f"{name}_shock"]))
                star = here & ~beyond
                fan = np.zeros_like(here)
            else:  # rarefaction: head, fan, tail (Toro eqs. 4.56, 4.63)
                head, tail = self.speeds[f"{name}_head"], self.speeds[f"{name}_tail"]
                beyond = here & ((S <= head) if side < 0 else (S >= head))
                star = here & ((S >= tail) if side < 0 else (S <= tail))
                fan = here & ~beyond & ~star
                base = 2.0 / (g + 1.0) + sign * (g - 1.0) / ((g + 1.0) * c) * (uk - S[fan])
                rho[fan] = rk * base ** (2.0 / (g - 1.0))
                u[fan] = 2.0 / (g + 1.0) * (sign * c + 0.5 * (g - 1.0) * uk + S[fan])
                p[fan] = pk * base ** (2.0 * g / (g - 1.0))
            rho[beyond], u[beyond], p[beyond] = rk, uk, pk
            rho[star], u[star], p[star] = rho_star, self.u_star, self.p_star
        return rho, u, p, p / ((g - 1.0) * rho)
