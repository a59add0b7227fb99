"""Elliptical drop: a circular patch of inviscid fluid in a linear strain flow stretches into an ellipse (Monaghan 1994)."""

import math

import numpy as np

from taisph.scene import Material, Scene
from taisph.geometry import lattice
from taisph.terms import ArtificialViscosity, Continuity, DensityDiffusion, PressureGradient, XSPH
from taisph.eos import tait
from taisph.scene.parameters import (checked, diffusion_delta, end_time, finite, frame_count, known_integrator,
                                     known_kernel, lattice_count, optional, positive, reference_density,
                                     smoothing_factor, speed_of_sound, viscosity_alpha, xsph_epsilon)


@checked(dx=positive, R=positive, A0=finite, rho0=reference_density, c0=speed_of_sound, h_factor=smoothing_factor,
         kernel=known_kernel, integrator=known_integrator, alpha=viscosity_alpha, delta=optional(diffusion_delta),
         xsph=optional(xsph_epsilon), t_end=end_time, frames=frame_count)
def elliptical_drop(
    dx: float = 0.025,
    R: float = 1.0,
    A0: float = 100.0,
    rho0: float = 1.0,
    c0: float = 1400.0,
    h_factor: float = 1.3,
    kernel: str = "spline",
    integrator: str = "pc",
    alpha: float = 0.1,
    delta: float | None = None,
    xsph: float | None = None,
    t_end: float = 0.0076,
    frames: int = 20,
):
    """A drop of radius R (m), no gravity, free surface all round, initial velocity
    u = -A0 x, v = A0 y. It stays an ellipse x^2/a^2 + y^2/b^2 = 1 with a b = R^2;
    a(t), b(t) follow an ODE (``taisph.validation.references.analytic.elliptical_drop``). Monaghan (1994) /
    PySPH set-up: R = 1, A0 = 100 1/s, rho0 = 1, c0 = 1400 m/s, t_end = 0.0076 s
    (b grows to 1.9445); dx = 0.025 by default (5024 particles).

    The density starts at the value that gives the exact initial pressure
    p = rho0 R^2 A0^2/2 (1 - r^2/R^2). alpha: Monaghan artificial viscosity (0.1 as
    in PySPH's WCSPH scheme; 0 to switch off); delta: density diffusion
    coefficient (0 or None: off); xsph: XSPH epsilon (0 or None: off).
    """
    lattice_count("elliptical_drop", "the drop", dx, ("R", R), ("R", R))
    fluid = Material("fluid", rho0=rho0, c0=c0, gamma=7.0)
    terms = [Continuity(), PressureGradient()]
    if alpha:
        terms.append(ArtificialViscosity(alpha=alpha))
    if delta:  # None or 0: no term
        terms.append(DensityDiffusion(delta=delta, hydrostatic=False))
    if xsph:  # None or 0: no term
        terms.append(XSPH(xsph_eps=xsph))
    h = h_factor * dx
    scene = Scene(name="elliptical_drop", dim=2, dx=dx, smoothing_length=h,
                  domain=((-1.1 * R, -2.1 * R), (1.1 * R, 2.1 * R)), materials=[fluid], terms=terms,
                  kernel=kernel, integrator=integrator, t_end=t_end, frames=frames,
                  description=f"drop of radius {R:g} m in the strain flow u = -{A0:g} x, v = {A0:g} y")
    n = math.ceil(R / dx)
    pts = lattice((-n * dx, -n * dx), (n * dx, n * dx), dx)
    r2 = (pts**2).sum(axis=1)
    pts = pts[r2 < R * R]
    r2 = r2[r2 < R * R]
    p0 = 0.5 * rho0 * R * R * A0 * A0
    velocity = np.stack([-A0 * pts[:, 0], A0 * pts[:, 1]], axis=1)
    scene.add_fluid(pts, velocity=velocity, density=tait.density(p0 * (1 - r2 / (R * R)), rho0, c0, 7.0))
    # the tip speeds up to about 1.4 A0 R by t = 0.0076 s: leave room for it in the CFL step
    scene.dt = 0.2 * h / (c0 + 1.5 * A0 * R)
    return scene


def headline(sim, out) -> list:
    """The semi-major axis b at the end, R max|y|(t) / max|y|(0) (the cloud's extent along y
    scaled by its initial extent), against Monaghan's ODE (taisph.validation.references.analytic;
    taisph.validation.runs.elliptical_drop measures it so)."""
    from taisph.run.results import Result
    from taisph.validation.references import analytic

    p = sim.scene.case_parameters
    y0 = np.abs(sim.scene.position[:, 1]).max()
    b = p["R"] * np.abs(sim.positions()[:, 1]).max() / y0
    exact = analytic.elliptical_drop(sim.time, R=p["R"], A0=p["A0"])[1]
    return [Result("b", float(b), "m", float(exact), "Monaghan (1994), the ODE of an inviscid drop",
                   f"R max|y| / max|y|(0) at t = {sim.time:.3g} s")]
