"""A drop held by surface tension in another fluid: at rest (the Laplace pressure) or started as an ellipse (its mode-2 oscillation)."""

import math

import numpy as np

from taisph.geometry import lattice
from taisph.scene import Material, Scene
from taisph.scene.parameters import (ParameterError, at_least, checked, end_time, frame_count, known_integrator,
                                     known_kernel, lattice_count, optional, positive, smoothing_factor)
from taisph.scene.phases import phase_densities, two_phase_terms


@checked(radius=positive, dx=optional(positive), box=positive, deformation=at_least(0), sigma=at_least(0),
         drop_density=positive, ambient_density=positive, drop_viscosity=at_least(0),
         ambient_viscosity=at_least(0), c0=optional(positive), background_pressure=optional(at_least(0)),
         h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator, t_end=optional(end_time),
         frames=frame_count)
def oscillating_drop(
    radius: float = 1e-3,
    dx: float | None = None,
    box: float = 4.0,
    deformation: float = 0.1,
    sigma: float = 0.0728,
    drop_density: float = 1000.0,
    ambient_density: float = 1000.0,
    drop_viscosity: float = 0.01,
    ambient_viscosity: float = 0.01,
    c0: float | None = None,
    background_pressure: float | None = None,
    h_factor: float = 1.3,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float | None = None,
    frames: int = 40,
) -> Scene:
    """A 2D drop of `drop_density` (material 0) in a periodic square box of side
    `box` x `radius` filled with fluid of `ambient_density` (material 1), no gravity.
    By default a millimetre drop with water's surface tension (sigma = 0.0728 N/m) in a
    liquid of the same density, both of viscosity 0.01 Pa s (Laplace number
    sigma rho R / mu^2 = 728), 20 particles across its radius (dx = radius / 20). Water in
    air at physical values (ambient_density = 1.2, viscosities 1e-3 and 1.8e-5) does not
    hold yet, nor does mu = 1e-3 in both: spurious currents grow until the density guard
    stops the run within a millisecond (docs/multiphase.md).

    The drop starts as the ellipse x^2/a^2 + y^2/b^2 = 1, a = R (1 + `deformation`),
    b = R / (1 + `deformation`) (the area of the circle of radius R), at rest;
    `deformation` = 0 is the circular drop at rest, whose inside pressure exceeds the
    outside by the Laplace pressure sigma / R. The ellipse oscillates in mode 2 at
    omega^2 = 6 sigma / ((rho_d + rho_a) R^3) (Lamb 1932, sec. 275, in 2D: n(n^2 - 1)
    sigma / ((rho_d + rho_a) R^3), n = 2), damped by viscosity.

    Sound speed: the drop's c0 = 10 x the capillary velocity sqrt(sigma / (rho_d R)), at
    least enough that the Laplace pressure compresses the drop by under 1 %; the ambient
    fluid's c0 sqrt(rho_d / rho_a), the same stiffness rho0 c0^2 / gamma in both
    (docs/multiphase.md). Background pressure: 0 by default. The
    initial density is that of each fluid's pressure: p_b outside, p_b + sigma / R inside.
    Terms: taisph.scene.phases.two_phase_terms (Hu & Adams 2006 momentum, viscosity and
    surface stress, Colagrossi & Landrini 2003 continuity). t_end: two periods of the
    mode-2 oscillation by default.
    """
    dx = radius / 20.0 if dx is None else dx
    side = box * radius
    lattice_count("oscillating_drop", "the box", dx, ("box x radius", side), ("box x radius", side))
    n = round(side / dx)
    if not math.isclose(n * dx, side, rel_tol=1e-9) or n < 12:
        raise ParameterError(f"oscillating_drop: dx = {dx:g} m must divide the box (box x radius = {side:g} m) into "
                             "a whole number of particles, at least 12")
    a, b = radius * (1.0 + deformation), radius / (1.0 + deformation)
    if 2.0 * a + 6.0 * h_factor * dx > side:
        raise ParameterError(f"oscillating_drop: the drop (2 a = {2 * a:g} m) must fit in the box ({side:g} m) with "
                             "three smoothing lengths to spare: use a larger box or a smaller deformation")
    laplace = sigma / radius
    capillary_speed = math.sqrt(sigma / (drop_density * radius))
    c0 = max(10.0 * capillary_speed, math.sqrt(laplace / (0.01 * drop_density))) if c0 is None else c0
    p_b = 0.0 if background_pressure is None else background_pressure
    omega = math.sqrt(6.0 * sigma / ((drop_density + ambient_density) * radius**3))
    if t_end is None and omega == 0.0:
        raise ParameterError("oscillating_drop: sigma = 0 gives the drop no oscillation to time the run by: "
                             "give t_end")
    t_end = 2.0 * (2.0 * math.pi / omega) if t_end is None else t_end
    drop = Material("drop", rho0=drop_density, c0=c0, gamma=7.0, viscosity=drop_viscosity, background_pressure=p_b)
    ambient = Material("ambient", rho0=ambient_density, c0=c0 * math.sqrt(drop_density / ambient_density),
                       gamma=7.0, viscosity=ambient_viscosity, background_pressure=p_b)
    scene = Scene(name="oscillating_drop", dim=2, dx=dx, smoothing_length=h_factor * dx,
                  domain=((0.0, 0.0), (side, side)), periodic=(True, True), materials=[drop, ambient],
                  terms=two_phase_terms(sigma=sigma, walls=False), kernel=kernel, integrator=integrator,
                  t_end=t_end, frames=frames,
                  description=(f"a {drop_density:g} kg/m^3 drop of radius {radius:g} m in {ambient_density:g} kg/m^3 "
                               f"fluid, sigma = {sigma:g} N/m, started as an ellipse of deformation {deformation:g}"))
    if 3 * scene.support_radius > side:
        raise ParameterError("oscillating_drop: the periodic box must span 3 kernel supports: use a smaller dx")
    points = lattice((0.0, 0.0), (side, side), dx)
    x, y = points[:, 0] - 0.5 * side, points[:, 1] - 0.5 * side
    inside = (x / a) ** 2 + (y / b) ** 2 < 1.0
    pressure = np.where(inside, p_b + laplace, p_b)
    for k, material in enumerate((drop, ambient)):
        sel = inside if k == 0 else ~inside
        scene.add_fluid(points[sel], material=k, density=phase_densities(material, pressure[sel]),
                        mass=material.rho0 * dx**2)
    return scene


def headline(sim, out) -> list:
    """The drop's pressure jump (mean pressure of the drop's particles within R/2 of its
    centre less the ambient's beyond 1.5 R) against Laplace's sigma / R, and the largest
    speed against the capillary velocity sigma / mu of the drop."""
    from taisph.run.results import Result
    from taisph.validation.phases import pressure_jump

    p = sim.scene.case_parameters
    radius, sigma = p["radius"], p["sigma"]
    jump = pressure_jump(sim, radius)
    speed = float(np.max(np.linalg.norm(sim.velocities(), axis=1)))
    at = f"at t = {sim.time:.3g} s"
    return [Result("pressure_jump", jump, "Pa", sigma / radius, "Laplace: sigma / R (2D)", at),
            Result("max_speed", speed, "m/s", None, "", f"{at}; capillary velocity sigma/mu = "
                   f"{sigma / max(p['drop_viscosity'], 1e-30):.3g} m/s")]
