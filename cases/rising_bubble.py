"""A bubble rising in a liquid column: the benchmark of Hysing et al. (2009), test cases 1 (density ratio 10) and 2 (1000)."""

import math

import numpy as np

from taisph.geometry import lattice, support_layers, wall_layers
from taisph.scene import Material, Scene
from taisph.scene.parameters import (ParameterError, checked, end_time, frame_count, known_integrator, known_kernel,
                                     integer, lattice_count, optional, positive, smoothing_factor)
from taisph.scene.phases import phase_densities, two_phase_terms

# Hysing et al. (2009), Int. J. Numer. Meth. Fluids 60:1259, table I: rho_1, rho_2, mu_1, mu_2, g, sigma
TEST_CASES = {1: (1000.0, 100.0, 10.0, 1.0, 0.98, 24.5), 2: (1000.0, 1.0, 10.0, 0.1, 0.98, 1.96)}


@checked(dx=positive, test_case=integer(at_least=1, at_most=2), c0=optional(positive), background_pressure=optional(positive),
         h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator, t_end=end_time,
         frames=frame_count)
def rising_bubble(
    dx: float = 1.0 / 40.0,
    test_case: int = 1,
    c0: float | None = None,
    background_pressure: float | None = None,
    h_factor: float = 1.3,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 3.0,
    frames: int = 30,
) -> Scene:
    """Hysing et al.'s 2D rising bubble: a 1 x 2 box of liquid (material 0: rho_1,
    mu_1) holding a bubble of radius 0.25 centred at (0.5, 0.5) (material 1: rho_2,
    mu_2), gravity g, surface tension sigma (``test_case`` 1: 1000/100, 10/1, 0.98,
    24.5; 2: 1000/1, 10/0.1, 0.98, 1.96). The benchmark has no-slip walls at the top and
    bottom and free-slip side walls; here the box is periodic in x, which for a flow
    symmetric about x = 0.5 is the same (the images of the bubble across free-slip walls at
    x = 0 and 1 are its periodic images), and the top and bottom are dummy walls (Adami
    et al. 2012) with no-slip viscosity.

    Sound speed c0 (the liquid's): by default 10 x the largest speed the benchmark
    reports (0.25), or enough that the column's weight compresses the liquid by under
    1 %, whichever is larger; the bubble's is c0 sqrt(rho_1 / rho_2), the same
    stiffness B = rho0 c0^2 / gamma in both phases (with one c0 the bubble's particles
    at the interface are stretched and thrown out within 0.3 s: docs/multiphase.md). Background pressure: the column's hydrostatic pressure
    rho_1 g H by default (docs/multiphase.md). Initial densities from the hydrostatic
    pressure of each phase. Default dx = 1/40 (a bubble 20 particles across).
    """
    rho_1, rho_2, mu_1, mu_2, g, sigma = TEST_CASES[int(test_case)]
    width, height, radius, centre = 1.0, 2.0, 0.25, (0.5, 0.5)
    lattice_count("rising_bubble", "the box", dx, ("width", width), ("height", height))
    n = round(width / dx)
    if not math.isclose(n * dx, width, rel_tol=1e-9) or n < 12:
        raise ParameterError(f"rising_bubble: dx = {dx:g} must divide the width 1 into a whole number of particles, "
                             "at least 12")
    weight = rho_1 * g * height
    c0 = max(10.0 * 0.25, math.sqrt(weight / (0.01 * rho_1))) if c0 is None else c0
    p_b = weight if background_pressure is None else background_pressure
    liquid = Material("liquid", rho0=rho_1, c0=c0, gamma=7.0, viscosity=mu_1, background_pressure=p_b)
    gas = Material("bubble", rho0=rho_2, c0=c0 * math.sqrt(rho_1 / rho_2), gamma=7.0, viscosity=mu_2, background_pressure=p_b)
    h = h_factor * dx
    layers = 3  # dummy-wall rows; checked against the kernel's support below
    scene = Scene(name="rising_bubble", dim=2, dx=dx, smoothing_length=h,
                  domain=((0.0, -layers * dx), (width, height + layers * dx)), periodic=(True, False),
                  materials=[liquid, gas], terms=two_phase_terms(sigma=sigma, walls=True, gravity=(0.0, -g)),
                  kernel=kernel, integrator=integrator, t_end=t_end, frames=frames,
                  description=(f"Hysing et al. (2009) rising bubble, test case {int(test_case)}: rho {rho_1:g}/{rho_2:g}, "
                               f"mu {mu_1:g}/{mu_2:g}, g {g:g}, sigma {sigma:g}"))
    layers = support_layers(scene.support_radius, dx)
    scene.domain = (np.array([0.0, -layers * dx]), np.array([width, height + layers * dx]))
    points = lattice((0.0, 0.0), (width, height), dx)
    inside = np.hypot(points[:, 0] - centre[0], points[:, 1] - centre[1]) < radius
    # hydrostatic pressure: the liquid column above (the bubble's own weight is negligible
    # against it), plus the Laplace jump sigma / R inside the bubble
    pressure = p_b + rho_1 * g * (height - points[:, 1]) + np.where(inside, sigma / radius, 0.0)
    for k, (material, sel) in enumerate(((liquid, ~inside), (gas, inside))):
        scene.add_fluid(points[sel], material=k, density=phase_densities(material, pressure[sel]),
                        mass=material.rho0 * dx**2)
    scene.add_walls(wall_layers((0.0, 0.0), (width, height), dx, layers, open_top=False, periodic=(True, False)))
    return scene


def headline(sim, out) -> list:
    """The bubble's centre of mass and rise velocity now (Hysing et al.'s quantities;
    their values at t = 3 for test case 1: y_c = 1.0813)."""
    from taisph.run.results import Result
    from taisph.validation.phases import bubble_state

    centre, velocity = bubble_state(sim)
    at = f"at t = {sim.time:.3g} s"
    ref = 1.0813 if sim.scene.case_parameters.get("test_case", 1) == 1 and abs(sim.time - 3.0) < 1e-9 else None
    return [Result("centre_of_mass", centre, "m", ref, "Hysing et al. (2009) test case 1, t = 3" if ref else "", at),
            Result("rise_velocity", velocity, "m/s", None, "", at)]
