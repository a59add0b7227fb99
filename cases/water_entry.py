"""Water entry of a cylinder: a 2D cylinder of half the water's density falls into still
water, plunges, bobs up and comes to float half submerged (after the experiments of
Greenhow & Lin 1983)."""

import math

import numpy as np

from taisph.eos import Tait
from taisph.geometry import lattice, support_layers
from taisph.geometry.shapes import ball, wall_layers
from taisph.probes import body, elevation
from taisph.scene import Material, Scene
from taisph.scene.parameters import (ParameterError, at_least, checked, diffusion_delta, end_time, frame_count,
                                     flag, gravity_magnitude, known_integrator, known_kernel, lattice_count, optional,
                                     positive, smoothing_factor, speed_of_sound, viscosity_alpha)
from taisph.scene.water import hydrostatic_density, sound_speed
from taisph.terms import (STANDARD_GRAVITY, AdamiWall, ArtificialViscosity, Continuity, DensityDiffusion, Gravity,
                          PressureGradient)

RHO_WATER = 1000.0


@checked(dx=positive, tank_width=positive, depth=positive, diameter=positive, density=positive, drop=at_least(0),
         alpha=viscosity_alpha, wall_friction=flag, delta=optional(diffusion_delta), c0=optional(speed_of_sound),
         h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel, integrator=known_integrator,
         t_end=end_time, frames=frame_count)
def water_entry(
    dx: float = 0.005,
    tank_width: float = 1.0,
    depth: float = 0.5,
    diameter: float = 0.11,
    density: float = 500.0,
    drop: float = 0.5,
    alpha: float = 0.1,
    wall_friction: bool = True,
    delta: float | None = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 3.0,
    frames: int = 60,
):
    """A cylinder of `diameter` (m) and `density` (kg/m^3) dropped from `drop` (m: its
    bottom's height above the water at release from rest) into the middle of a
    `tank_width` tank of still water `depth` deep (defaults, after Greenhow & Lin 1983,
    "Nonlinear free surface effects: experiments and theory", MIT report 83-19: D = 0.11 m,
    500 kg/m^3, drop 0.5 m; a 1 m x 0.5 m tank; dx = 0.005 m, D/dx = 22: 20 000 fluid and
    384 body particles).

    The flight is not simulated: the cylinder starts with its bottom two kernel supports
    above the water (4 h), falling at the speed it has there, sqrt(2 g (drop - 4 h)), so it
    meets the water at sqrt(2 g drop) = 3.13 m/s (from drop < 4 h: released from rest at
    drop). It is a floating body (:meth:`taisph.Scene.add_body`) filled with the lattice
    points inside the circle, its mass `density` x their area; it floats at rest with its
    centre at the water's level (`density` = 500: half submerged), which the displaced
    water raises by the submerged area / tank_width (3.8 mm with the defaults:
    :func:`expected`). Dummy walls, Monaghan alpha = 0.1, acting between the fluid and the
    walls and cylinder too (`wall_friction`: without it, thin sheets of water sliding
    down the cylinder's sides at the waterline come up to 0.65 dx inside its surface at
    dx = 0.01 m, with it 0.08 dx), density diffusion delta = 0.1, c0 = 10 max(sqrt(2 g depth), entry speed); the tank is open at
    the top (splashes leave and come back).

    Probes (``python -m taisph water_entry`` writes OUT/probes.csv): the body probe
    ``cylinder`` every 10 steps (``cylinder_y``: its centre's height above the floor;
    velocities and the fluid's force) and the wave gauge ``gauge`` at x = 0.1 tank_width."""
    radius = diameter / 2
    if diameter > 0.5 * tank_width or diameter > 0.5 * depth:
        raise ParameterError(f"water_entry: the cylinder (diameter = {diameter:g} m) must be at most half the "
                             f"tank's width (tank_width = {tank_width:g} m) and half the water's depth "
                             f"(depth = {depth:g} m)")
    if diameter < 4 * dx:
        raise ParameterError(f"water_entry: dx = {dx:g} m does not resolve the cylinder (diameter = {diameter:g} m "
                             "needs diameter / dx >= 4)")
    lattice_count("water_entry", "the tank", dx, ("tank_width", tank_width), ("depth", depth))
    h = h_factor * dx
    start = min(drop, 4 * h)  # the bottom's height above the water at t = 0
    speed = math.sqrt(2 * g * (drop - start))
    entry = math.sqrt(2 * g * drop)
    c0 = sound_speed(g, depth, entry) if c0 is None else c0
    water = Material("water", rho0=RHO_WATER, c0=c0, gamma=7.0)
    terms = [Continuity(walls=True), PressureGradient(walls=True),
             ArtificialViscosity(alpha=alpha, walls=wall_friction), Gravity(gravity=(0.0, -g)), AdamiWall()]
    if delta:
        terms.append(DensityDiffusion(delta=delta))
    top = math.ceil((2 * depth + start + diameter) / dx) * dx  # the walls' height, on the lattice
    scene = Scene(name="water_entry", dim=2, dx=dx, smoothing_length=h, domain=((0.0, 0.0), (1.0, 1.0)),
                  open_faces=("+y",), remove_escaped=True, materials=[water], eos=Tait(), terms=terms,
                  kernel=kernel, integrator=integrator, t_end=t_end, frames=frames,
                  description=f"cylinder, D = {diameter:g} m, {density:g} kg/m^3, dropped {drop:g} m (entry at "
                              f"{entry:.3g} m/s) into {depth:g} m of still water in a {tank_width:g} m tank")
    layers = support_layers(scene.support_radius, dx)
    pad = layers * dx
    scene.domain = (np.array([-pad - dx, -pad - dx]), np.array([tank_width + pad + dx, top + pad + dx + 0.5 * top]))
    fluid = lattice((0.0, 0.0), (tank_width, depth), dx)
    scene.add_fluid(fluid, density=hydrostatic_density(water, g, depth - fluid[:, 1]))
    scene.add_walls(wall_layers((0.0, 0.0), (tank_width, top), dx, layers, vertical_axis=1, open_top=True))
    # the disc's lattice continues the fluid's (its centre on a multiple of dx across)
    centre = (round(0.5 * tank_width / dx) * dx, depth + start + radius)
    scene.add_body("cylinder", ball(centre, radius, dx), density=density, velocity=(0.0, -speed))
    scene.probes += [body("cylinder", every=10),
                     elevation("gauge", at=(0.1 * tank_width,), every=10)]
    return scene


def expected(dx=0.005, tank_width=1.0, depth=0.5, diameter=0.11, density=500.0) -> dict:
    """Where the cylinder floats at rest (Archimedes): its submerged area m / rho_w, the
    water's level raised by it over the tank's width, and its centre's height (the
    level plus R - draft, the draft from the circular segment's area, by bisection), for
    the disc of lattice points :func:`water_entry` builds (its area N dx^2, the radius
    sqrt(N dx^2 / pi) of that area)."""
    n = len(ball((0.0, 0.0), diameter / 2, dx))
    area = n * dx**2
    r = math.sqrt(area / math.pi)
    submerged = density / RHO_WATER * area
    level = depth + submerged / tank_width

    def segment(d):  # the area of the disc below a line d above its bottom
        return r * r * math.acos((r - d) / r) - (r - d) * math.sqrt(max(0.0, 2 * r * d - d * d))

    lo, hi = 0.0, 2 * r
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if segment(mid) < submerged else (lo, mid)
    draft = 0.5 * (lo + hi)
    return dict(particles=n, area=area, radius=r, mass=density * area, submerged=submerged, level=level,
                draft=draft, centre=level - draft + r)


def headline(sim, out) -> list:
    """The cylinder's centre height at the end against where it floats at rest (Archimedes,
    :func:`expected`: reached after the plunge and the bobbing have died out)."""
    from taisph.run.results import Result

    p = sim.scene.case_parameters
    rest = expected(p["dx"], p["tank_width"], p["depth"], p["diameter"], p["density"])
    centre = float(sim.bodies()["cylinder"].position[1])
    return [Result("centre_height", centre, "m", rest["centre"] if p["density"] < RHO_WATER else None,
                   "Archimedes, floating at rest" if p["density"] < RHO_WATER else "",
                   f"the cylinder's centre above the floor at t = {sim.time:.3g} s")]
