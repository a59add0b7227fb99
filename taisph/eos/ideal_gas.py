"""Ideal-gas equation of state, for compressible flow.

    p = (gamma - 1) rho e,        c = sqrt(gamma p / rho) = sqrt(gamma (gamma - 1) e),

with e the specific internal energy (J/kg), stored per particle as ``energy`` and
evolved by :class:`taisph.terms.InternalEnergy` (seed eq. 11). Each material (a
:class:`taisph.scene.Gas`) gives its own ratio of specific heats gamma (column of the
material table). The sound speed is per particle (row ``sound_speed``): the artificial
viscosity uses it, and so can a time-step rule.

A negative internal energy is not clamped: it makes the sound speed NaN, which no
later step can hide (the gas tests check that e and rho stay positive).
"""

import copy

import numpy as np
import taichi as ti

from ..messages import InputError


@ti.data_oriented
class IdealGas:
    """The equation of state of a gas scene (``Scene(eos=IdealGas(), ...)``)."""

    name = "ideal_gas"
    columns = ("gamma",)  # per-material constants (material table)
    scalars = ("sound_speed", "energy")  # per-particle quantities it stores
    derived = ("sound_speed",)  # ... recomputed from the state every step (not carried)
    outputs = ("energy", "sound_speed")  # written to the ParaView frames

    def material_row(self, material) -> list:
        return [material.gamma]

    def bind(self, layout, material_cols):
        """A copy with compile-time rows attached (the scene's own stays picklable)."""
        bound = copy.copy(self)
        bound.q = layout.q
        bound.m = material_cols
        return bound

    def compile_key(self):
        return ("ideal_gas",)

    def check(self, scene) -> None:
        """Raise ValueError if the scene cannot be simulated with this EOS."""
        for m in scene.materials:
            if not (np.isfinite(m.gamma) and m.gamma > 1.0):
                raise InputError(f"material {m.name!r}: an ideal gas needs gamma > 1, got {m.gamma!r}")
        e = scene.quantities.get("energy")
        if e is None:
            raise InputError(f"scene {scene.name!r}: an ideal gas needs the particles' internal energy "
                             "(add_fluid(..., energy=...))")
        if np.any(np.asarray(e) < 0):
            raise InputError(f"scene {scene.name!r}: internal energy must be >= 0")

    def max_sound_speed(self, scene) -> float:
        """Largest sound speed of the scene's initial state (for a CFL time step)."""
        gamma = np.array([m.gamma for m in scene.materials])[scene.material]
        e = np.asarray(scene.quantities.get("energy", np.zeros(scene.n)))
        return float(np.max(np.sqrt(gamma * (gamma - 1.0) * np.maximum(e, 0.0)), initial=0.0))

    @ti.func
    def derive(self, s: ti.template(), i):
        """Pressure and sound speed of (sorted) particle i from its density and energy."""
        q = ti.static(self.q)
        gamma = s.mat[s.Si[q.material, i], self.m.gamma]
        e = s.Ss[q.energy, i]
        s.Ss[q.pressure, i] = (gamma - 1.0) * s.Ss[q.density, i] * e
        s.Ss[q.sound_speed, i] = ti.sqrt(gamma * (gamma - 1.0) * e)

    @ti.func
    def sound_speed(self, s: ti.template(), i):
        return s.Ss[self.q.sound_speed, i]


def pressure(rho, e, gamma=1.4):
    """p = (gamma - 1) rho e (numpy), for initial conditions and tests."""
    return (gamma - 1.0) * np.asarray(rho) * np.asarray(e)


def energy(p, rho, gamma=1.4):
    """Specific internal energy e = p / ((gamma - 1) rho) (numpy)."""
    return np.asarray(p) / ((gamma - 1.0) * np.asarray(rho))


def sound_speed(p, rho, gamma=1.4):
    """c = sqrt(gamma p / rho) (numpy)."""
    return np.sqrt(gamma * np.asarray(p) / np.asarray(rho))
