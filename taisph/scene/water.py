"""The standard water physics of the free-surface cases, the scene files and the seed's
files, written once: the sound speed of the weakly compressible fluid, the strength of
the Lennard-Jones walls, and the density of a column at rest under gravity.

Each function is the formula as the dam break (``cases/dam_break.py``) has always
evaluated it, operation for operation, so the scenes built with it are bit-for-bit
those built before it existed.
"""

from __future__ import annotations

import math

import numpy as np

from ..eos import tait

# The sound speed is this many times the largest expected flow speed: the density then
# varies by about 1 / SPEED_RATIO^2 = 1 % (Monaghan 1994).
SPEED_RATIO = 10.0
# The Lennard-Jones wall strength in units of g H / r0 (Monaghan 1994; the seed's eq. 13).
WALL_STRENGTH = 5.0


def sound_speed(g: float, height: float, speed: float = 0.0) -> float:
    """c0 = 10 max(sqrt(2 g H), |v|max): ten times the fastest speed the flow reaches,
    that of a fall through the fluid's height H (m) under gravity g (m/s^2), or its
    fastest initial speed (m/s) if larger (Monaghan 1994, "Simulating free surface flows
    with SPH", J. Comput. Phys. 110; Monaghan 2005, Rep. Prog. Phys. 68, sec. 3.7).
    Zero without gravity and motion: the caller says what to set."""
    return SPEED_RATIO * max(math.sqrt(2.0 * g * height), speed)


def lennard_jones_strength(g: float, height: float, r0: float, speed: float = 0.0) -> float:
    """D = 5 g H / r0: the strength (m/s^2) of the Lennard-Jones wall force of
    Monaghan (1994) (the seed's eq. 13), of the order of the square of the largest
    speed: g H, from the fluid's height H (m) under gravity g (m/s^2), or v^2/2 of the
    fastest initial speed (m/s) if larger; r0 (m) is the force's range, the wall
    particles' spacing."""
    head = 0.5 * speed**2
    if g * height >= head:
        return WALL_STRENGTH * g * height / r0
    return WALL_STRENGTH * head / r0


def hydrostatic_density(material, g: float, depth) -> np.ndarray:
    """The density of water at rest at `depth` (m) below its free surface: the Tait
    equation (:mod:`taisph.eos.tait`) inverted at the hydrostatic pressure
    p = rho0 g depth, so the column starts in equilibrium, not with the pressure waves
    a uniform density would send (Monaghan 1994; Adami et al. 2012)."""
    return tait.density(material.rho0 * g * np.asarray(depth, float), material.rho0, material.c0, material.gamma)
