"""2D dam break flowing over a triangular wedge on the tank floor (after Monaghan 1994; seed Figure 2)."""

import numpy as np

from taisph.geometry import polyline
from taisph.scene import Material, Scene
from taisph.geometry import box_walls, lattice
from taisph.terms import STANDARD_GRAVITY, ArtificialViscosity, Continuity, Gravity, LennardJonesWall, PressureGradient
from taisph.scene.names import UP
from taisph.scene.water import hydrostatic_density, lennard_jones_strength, sound_speed
from taisph.scene.parameters import (ParameterError, checked, end_time, frame_count, gravity_magnitude,
                                     known_integrator, known_kernel, lattice_count, optional, positive,
                                     smoothing_factor, speed_of_sound, viscosity_alpha)


@checked(dx=positive, width=positive, height=positive, tank_width=positive, tank_height=positive,
         wedge_start=positive, wedge_base=positive, wedge_height=positive, alpha=viscosity_alpha,
         c0=optional(speed_of_sound), h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel,
         integrator=known_integrator, t_end=end_time, frames=frame_count)
def dam_break_wedge(
    dx: float = 0.02,
    width: float = 1.0,
    height: float = 2.0,
    tank_width: float = 4.0,
    tank_height: float = 4.0,
    wedge_start: float = 2.0,
    wedge_base: float = 1.0,
    wedge_height: float = 0.5,
    alpha: float = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 1.5,
    frames: int = 30,
) -> Scene:
    """The dam break of ``dam_break`` (a `width` x `height` water column at the left
    wall of a `tank_width` tank) with a symmetric triangular wedge on the floor: base
    from x = `wedge_start` to `wedge_start` + `wedge_base`, apex `wedge_height` high
    (defaults: 2 m to 3 m, apex 0.5 m at x = 2.5 m, so both faces slope at 45 deg).

    Monaghan (1994) simulated a dam break over a wedge; his dimensions were not
    available to us, so this geometry is our own (the seed's Figure 2 shows the
    same kind of flow). Physics and numerical defaults as ``dam_break``: h = 1.3 dx,
    c0 = 10 sqrt(2 g H), alpha = 0.1, Lennard-Jones walls of particles dx/2 apart
    (the wedge's two faces too) with r0 = dx/2 and D = 5 g H / r0, a column in
    hydrostatic equilibrium. Default dx = 0.02 m: 5000 fluid particles.
    """
    if not (width < wedge_start and wedge_start + wedge_base < tank_width):
        raise ParameterError(f"dam_break_wedge: the wedge (from wedge_start = {wedge_start:g} m to wedge_start + "
                             f"wedge_base = {wedge_start + wedge_base:g} m) must lie on the floor between the column "
                             f"(width = {width:g} m) and the right wall (tank_width = {tank_width:g} m)")
    if height > tank_height or wedge_height >= tank_height:
        raise ParameterError(f"dam_break_wedge: the column (height = {height:g} m) and the wedge (wedge_height = "
                             f"{wedge_height:g} m) must fit under tank_height = {tank_height:g} m")
    lattice_count("dam_break_wedge", "the water column", dx, ("width", width), ("height", height))
    lattice_count("dam_break_wedge", "the tank", dx, ("tank_width", tank_width), ("tank_height", tank_height))
    c0 = sound_speed(g, height) if c0 is None else c0
    water = Material("water", rho0=1000.0, c0=c0, gamma=7.0)
    spacing = r0 = dx / 2.0
    scene = Scene(
        name="dam_break_wedge",
        dim=2,
        dx=dx,
        smoothing_length=h_factor * dx,
        domain=(np.array([-dx, -dx]), np.array([tank_width + dx, tank_height + dx])),
        materials=[water],
        terms=[
            Continuity(),
            PressureGradient(),
            ArtificialViscosity(alpha=alpha),
            Gravity(gravity=(0.0, -g)),
            LennardJonesWall(lj_strength=lennard_jones_strength(g, height, r0), lj_cutoff=r0),
        ],
        kernel=kernel,
        integrator=integrator,
        t_end=t_end,
        frames=frames,
        description=(f"{width:g} m x {height:g} m water column flowing over a {wedge_height:g} m high, "
                     f"{wedge_base:g} m wide wedge in a {tank_width:g} m tank"),
    )
    fluid = lattice([0.0, 0.0], [width, height], dx)
    rho = hydrostatic_density(water, g, height - fluid[:, UP])
    scene.add_fluid(fluid, density=rho)
    tank = box_walls([0.0, 0.0], [tank_width, tank_height], spacing)
    under_wedge = ((np.abs(tank[:, 1]) < 1e-9) & (tank[:, 0] > wedge_start + 1e-9)
                   & (tank[:, 0] < wedge_start + wedge_base - 1e-9))
    faces = polyline([(wedge_start, 0.0), (wedge_start + 0.5 * wedge_base, wedge_height),
                      (wedge_start + wedge_base, 0.0)], spacing)[1:-1]  # the base corners are floor particles
    scene.add_walls(np.concatenate([tank[~under_wedge], faces]))
    return scene
