"""First-order wave-maker theory and the motions of wave makers, for a moving wall of
particles: a piston or a bottom-hinged flap making regular waves, and a piston making a
solitary wave. Pure numpy, so a scene, a test or a plot can use it without Taichi.

    motion = piston(height=0.05, period=1.5, depth=0.5)
    x, u, a = motion.position(t), motion.velocity(t), motion.acceleration(t)

Each motion starts at t = 0 from rest (a regular wave with ramp = 0 from full speed) and
its velocity and acceleration are analytic, so a wall driven by them carries no
finite-difference noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..messages import InputError
from ..terms.gravity import STANDARD_GRAVITY

G = STANDARD_GRAVITY  # m/s^2, the default g of the wave makers' dispersion relations
MICHE = 0.142  # breaking steepness H/L of deep-water waves (Miche 1944)
MCCOWAN = 0.78  # highest solitary wave H/h (McCowan 1894)
SOLITARY_TAIL = 1e-5  # fraction of Goring's stroke left out at each end of the motion


@dataclass(frozen=True)
class Motion:
    """The motion of a wave maker along one degree of freedom.

    ``kind`` is "translation" (a piston: displacement along its axis, m) or "rotation" (a flap:
    angle about its hinge, rad). ``position``, ``velocity`` and ``acceleration`` take an
    array of times (s) and return arrays of the same shape: the displacement or angle and
    its first and second time derivatives. ``stroke`` is the largest |position| the motion
    reaches (m or rad); ``duration`` (s) is when it has settled or a table of it should end
    (``math.inf`` for a periodic motion)."""

    kind: str
    duration: float
    stroke: float
    description: str
    position: Callable[[np.ndarray], np.ndarray]
    velocity: Callable[[np.ndarray], np.ndarray]
    acceleration: Callable[[np.ndarray], np.ndarray]


def _require_positive(name, value, unit):
    # `not value > 0` also refuses NaN, which no comparison accepts
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"{name} must be a positive number ({unit}), got {value!r}")


def wavenumber(period, depth, g=G) -> float:
    """The wavenumber k (1/m) of a linear wave of period T in depth h: the root of the
    dispersion relation

        omega^2 = g k tanh(k h),   omega = 2 pi / T

    (Airy 1845; e.g. Dean & Dalrymple 1991, "Water wave mechanics for engineers and
    scientists", World Scientific, eq. 4.34). Newton's iteration on kh tanh kh = omega^2 h/g,
    started from Eckart's approximation kh = y / sqrt(tanh y), y = omega^2 h / g (Eckart 1952,
    "The propagation of gravity waves from deep to shallow water", NBS Circular 521), which
    is the deep-water root (kh = y) and the shallow-water root (kh = sqrt y) in the two
    limits and within 5 % between; iterated until a step is below 1e-12 of kh.
    """
    _require_positive("period", period, "s")
    _require_positive("depth", depth, "m")
    _require_positive("g", g, "m/s^2")
    omega = 2.0 * math.pi / period
    y = omega * omega * depth / g
    kh = y / math.sqrt(math.tanh(y))
    for _ in range(50):
        t = math.tanh(kh)
        # d/d(kh) of kh tanh kh is tanh kh + kh sech^2 kh; 1 - tanh^2 does not overflow as cosh^2 does
        step = (kh * t - y) / (t + kh * (1.0 - t * t))
        kh -= step
        if abs(step) <= 1e-12 * kh:
            return kh / depth
    raise RuntimeError(f"dispersion relation did not converge for period {period!r}, depth {depth!r}")


def piston_transfer(kh) -> float:
    """Wave height over stroke of a piston wave maker in first-order theory,

        H / S = 2 (cosh 2kh - 1) / (sinh 2kh + 2kh)

    (Dean & Dalrymple 1991, "Water wave mechanics for engineers and scientists", World
    Scientific, sec. 6.2): kh in shallow water (kh -> 0), 2 in deep water.
    """
    _require_positive("kh", kh, "dimensionless")
    x = float(kh)
    # the same ratio divided through by sinh 2kh (cosh 2kh - 1 = 2 sinh^2 kh): cosh and sinh of
    # 2kh overflow beyond kh ~ 355, and x / sinh 2x just goes to 0 there
    with np.errstate(over="ignore"):
        return float(2.0 * np.tanh(x) / (1.0 + 2.0 * x / np.sinh(2.0 * x)))


def flap_transfer(kh) -> float:
    """Wave height over stroke of a flap hinged at the bottom in first-order theory, S the
    stroke at the still-water level,

        H / S = 4 (sinh kh / kh) (kh sinh kh - cosh kh + 1) / (sinh 2kh + 2kh)

    (Dean & Dalrymple 1991, "Water wave mechanics for engineers and scientists", World
    Scientific, sec. 6.2): kh/2 in shallow water, 2 - 2/kh towards deep water.
    """
    _require_positive("kh", kh, "dimensionless")
    x = float(kh)
    with np.errstate(over="ignore"):
        # cosh kh - 1 as 2 sinh^2(kh/2) for small kh (the difference is all rounding there),
        # divided by cosh kh: the ratio, divided through by sinh kh cosh kh, cannot overflow
        one_minus_sech = 2.0 * np.sinh(x / 2) ** 2 / np.cosh(x) if x < 1.0 else 1.0 - 1.0 / np.cosh(x)
        return float(2.0 * (x * np.tanh(x) - one_minus_sech) / (x * (1.0 + 2.0 * x / np.sinh(2.0 * x))))


def _regular_wave(height, period, depth, ramp, g):
    """kh and the wavelength of a regular wave, after refusing what first-order theory cannot make."""
    _require_positive("height", height, "m")
    if not (ramp >= 0 and math.isfinite(ramp)):
        raise InputError(f"ramp must be a number of periods >= 0, got {ramp!r}")
    k = wavenumber(period, depth, g)
    wavelength = 2.0 * math.pi / k
    limit = MICHE * math.tanh(k * depth)
    if height / wavelength >= limit:
        raise InputError(
            f"height = {height!r} m is too high: its steepness height/wavelength = {height / wavelength:.4g} "
            f"(wavelength {wavelength:.4g} m for period {period!r} s, depth {depth!r} m) is at or above the "
            f"breaking limit 0.142 tanh(kh) = {limit:.4g} (Miche 1944)")
    return k * depth, wavelength


def _ramped_sine(amplitude, omega, ramp_time):
    """f(t) = a r(t) sin(omega t) and its two derivatives, r the ramp of :func:`piston`."""

    def parts(t):
        t = np.asarray(t, dtype=float)
        if ramp_time > 0:
            p = math.pi / ramp_time
            phase = p * np.clip(t, 0.0, ramp_time)  # pi past the ramp: r = 1, r' = r'' = 0 there
            r, dr, ddr = 0.5 * (1 - np.cos(phase)), 0.5 * p * np.sin(phase), 0.5 * p * p * np.cos(phase)
            ddr = np.where(t < ramp_time, ddr, 0.0)
        else:
            r, dr, ddr = np.ones_like(t), np.zeros_like(t), np.zeros_like(t)
        on = t >= 0  # at rest before the start
        s, c = np.sin(omega * t), np.cos(omega * t)
        return on, r, dr, ddr, s, c

    def position(t):
        on, r, _, _, s, _ = parts(t)
        return np.where(on, amplitude * r * s, 0.0)

    def velocity(t):
        on, r, dr, _, s, c = parts(t)
        return np.where(on, amplitude * (dr * s + r * omega * c), 0.0)

    def acceleration(t):
        on, r, dr, ddr, s, c = parts(t)
        return np.where(on, amplitude * (ddr * s + 2 * dr * omega * c - r * omega * omega * s), 0.0)

    return position, velocity, acceleration


def piston(height, period, depth, ramp=2.0, g=G) -> Motion:
    """A piston making regular waves of height H and period T in depth h (first-order theory).

    Stroke S = H / (H/S)(kh), :func:`piston_transfer` (Dean & Dalrymple 1991, "Water wave
    mechanics for engineers and scientists", World Scientific, sec. 6.2), and displacement

        x(t) = (S/2) r(t) sin(omega t),   r(t) = (1 - cos(pi t / T_r)) / 2 for 0 <= t < T_r,
                                          r = 1 after, T_r = ramp * T

    so the piston starts at rest and reaches full amplitude S/2 after ``ramp`` periods; the
    velocity and acceleration are x's derivatives by the product rule. The velocity is
    continuous at T_r; the acceleration too when 2 ramp is a whole number (sin(omega T_r) = 0,
    as for the default), otherwise it steps by (S/2)(pi/T_r)^2 sin(omega T_r) / 2 there.

    ``stroke`` of the returned motion is its largest displacement S/2 (the description gives
    S). Refuses ramp < 0, height <= 0, and a steepness H/L >= 0.142 tanh kh (Miche 1944,
    "Mouvements ondulatoires de la mer en profondeur constante ou décroissante", Annales des
    Ponts et Chaussées), where waves break.
    """
    kh, wavelength = _regular_wave(height, period, depth, ramp, g)
    stroke = height / piston_transfer(kh)
    position, velocity, acceleration = _ramped_sine(stroke / 2, 2 * math.pi / period, ramp * period)
    return Motion("translation", math.inf, stroke / 2,
                  f"piston, regular waves H = {height:g} m, T = {period:g} s in depth {depth:g} m "
                  f"(kh = {kh:.4g}, wavelength {wavelength:.4g} m): stroke S = {stroke:.4g} m, "
                  f"ramped over {ramp:g} periods", position, velocity, acceleration)


def flap(height, period, depth, ramp=2.0, g=G) -> Motion:
    """A flap hinged at the bottom making regular waves of height H and period T in depth h.

    Stroke at the still-water level S = H / (H/S)(kh), :func:`flap_transfer` (Dean &
    Dalrymple 1991, "Water wave mechanics for engineers and scientists", World Scientific,
    sec. 6.2). The position is the flap's rotation about its hinge at the bottom, positive
    towards +x (the top moves to +x), in rad:

        theta(t) = atan(S / (2 h)) r(t) sin(omega t)

    with the ramp r(t) of :func:`piston`, so the still-water level moves by about
    (S/2) sin(omega t) once ramped. ``stroke`` is the largest angle atan(S / (2 h)).
    Refuses what :func:`piston` refuses.
    """
    kh, wavelength = _regular_wave(height, period, depth, ramp, g)
    stroke = height / flap_transfer(kh)
    angle = math.atan(stroke / (2 * depth))
    position, velocity, acceleration = _ramped_sine(angle, 2 * math.pi / period, ramp * period)
    return Motion("rotation", math.inf, angle,
                  f"flap hinged at the bottom, regular waves H = {height:g} m, T = {period:g} s in depth "
                  f"{depth:g} m (kh = {kh:.4g}, wavelength {wavelength:.4g} m): stroke S = {stroke:.4g} m "
                  f"at the still-water level, {angle:.4g} rad, ramped over {ramp:g} periods",
                  position, velocity, acceleration)


def solitary_piston(height, depth, g=G) -> Motion:
    """A piston making a solitary wave of height H in depth h (Goring 1978, "Tsunamis: the
    propagation of long waves onto a shelf", PhD thesis, California Institute of Technology,
    report KH-R-38; Goring & Raichlen 1980, "The generation of long waves in the laboratory",
    Proc. 17th International Conference on Coastal Engineering).

    The piston moves with the depth-averaged velocity under the wave, dX/dt = c eta / (h + eta),
    of Boussinesq's solitary wave eta = H sech^2(kappa (c t - x)), kappa = sqrt(3 H / (4 h^3)),
    c = sqrt(g (h + H)). Integrated, this is Goring's implicit trajectory, written to run
    from 0 to the stroke S = 2 H / (kappa h) = sqrt(16 H h / 3):

        X(t) = (H / (kappa h)) (1 + tanh(phi)),   phi = kappa (c (t - t_c) - X + H / (kappa h))

    solved for X by Newton's iteration at each time (to 1e-12 m). The motion is symmetric
    about its middle t_c, where the velocity is largest, c H / (h + H). t_c is chosen so that
    X(0) = 1e-5 S (``SOLITARY_TAIL``), and ``duration`` = 2 t_c, where X = S - 1e-5 S: before
    0 the piston rests at 0 and after ``duration`` at S (steps of 1e-5 S, and of the
    velocity, 4e-5 c H / h, neglected). Velocity c eta/(h + eta) with eta = H sech^2(phi) and
    acceleration, its derivative, -2 c^2 kappa q tanh(phi) / (1 + q)^3, q = eta / h, exact.
    Refuses H/h >= 0.78, higher than the highest solitary wave (McCowan 1894, "On the
    highest wave of permanent type", Philosophical Magazine).
    """
    _require_positive("height", height, "m")
    _require_positive("depth", depth, "m")
    _require_positive("g", g, "m/s^2")
    if height / depth >= MCCOWAN:
        raise InputError(f"height = {height!r} m is too high for depth = {depth!r} m: height/depth = "
                         f"{height / depth:.4g} is at or above {MCCOWAN} (McCowan 1894), where solitary waves break")
    kappa = math.sqrt(3 * height / (4 * depth**3))
    c = math.sqrt(g * (depth + height))
    half = height / (kappa * depth)  # S / 2
    stroke = 2 * half
    # at t = 0, X = tail S: (1 + tanh phi)/2 = tail, and phi = kappa (-c t_c - X + S/2)
    t_c = (math.atanh(1 - 2 * SOLITARY_TAIL) / kappa + half - SOLITARY_TAIL * stroke) / c
    duration = 2 * t_c
    # 1e-12 m unless that is below rounding of X (a stroke of kilometres)
    tolerance = max(1e-12, 8 * np.finfo(float).eps * stroke)

    def phase(t):
        """phi at times t (clipped to the motion), by Newton on F(X) = X - S/2 (1 + tanh phi)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, duration)
        x = half * (1 + np.tanh(kappa * c * (t - t_c)))  # X with the -X + S/2 of phi left out
        for _ in range(100):
            phi = kappa * (c * (t - t_c) - x + half)
            # F' = 1 + (H/h) sech^2 phi >= 1: Newton cannot stall
            step = (x - half * (1 + np.tanh(phi))) / (1 + height / depth / np.cosh(phi) ** 2)
            x = x - step
            if np.all(np.abs(step) <= tolerance):
                return kappa * (c * (t - t_c) - x + half), x
        raise RuntimeError("Goring's trajectory did not converge")

    def q(phi):  # eta / h
        return height / depth / np.cosh(phi) ** 2

    def within(t, inside, before, after):
        t = np.asarray(t, dtype=float)
        return np.where(t < 0, before, np.where(t > duration, after, inside))

    def position(t):
        return within(t, phase(t)[1], 0.0, stroke)

    def velocity(t):
        qq = q(phase(t)[0])
        return within(t, c * qq / (1 + qq), 0.0, 0.0)

    def acceleration(t):
        phi = phase(t)[0]
        qq = q(phi)
        return within(t, -2 * c * c * kappa * qq * np.tanh(phi) / (1 + qq) ** 3, 0.0, 0.0)

    return Motion("translation", duration, stroke,
                  f"piston, solitary wave H = {height:g} m in depth {depth:g} m (Goring 1978): stroke "
                  f"{stroke:.4g} m in {duration:.4g} s, celerity {c:.4g} m/s", position, velocity, acceleration)
