"""A circular (2D) or spherical (3D) body of water falling onto a 45 degree inclined plane (seed Figure 3)."""

import math

import numpy as np

from taisph.geometry import ball, container_layers, extrude, polyline, side_walls, support_layers
from taisph.scene import Material, Scene
from taisph.terms import (STANDARD_GRAVITY, AdamiWall, ArtificialViscosity, Continuity, Gravity, LennardJonesWall,
                          PressureGradient)
from taisph.scene.water import lennard_jones_strength, sound_speed
from taisph.scene.parameters import (ParameterError, at_least, checked, end_time, frame_count, gravity_magnitude,
                                     known_integrator, known_kernel, known_solver, lattice_count, one_of, optional,
                                     positive, smoothing_factor, speed_of_sound, viscosity_alpha)

SQRT2 = math.sqrt(2.0)


@checked(dim=one_of(2, 3), dx=optional(positive), radius=positive, fall=at_least(0), impact_x=positive,
         incline=positive, floor=at_least(0), tank_height=positive, depth=positive, side_wall_height=positive,
         alpha=viscosity_alpha, c0=optional(speed_of_sound), h_factor=smoothing_factor, g=gravity_magnitude,
         kernel=known_kernel, integrator=known_integrator, t_end=end_time, frames=frame_count,
         walls=optional(one_of("lj", "dummy")), solver=optional(known_solver))
def drop_on_incline(
    dim: int = 2,
    dx: float | None = None,
    radius: float = 0.2,
    fall: float = 0.3,
    impact_x: float = 0.5,
    incline: float = 1.6,
    floor: float = 1.0,
    tank_height: float = 2.2,
    depth: float = 0.8,
    side_wall_height: float = 0.6,
    alpha: float = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 0.7,
    frames: int = 28,
    walls: str | None = None,
    solver: str | None = None,
) -> Scene:
    """A drop of water of `radius` (m), at rest, falls `fall` (m) before it touches a
    45 deg plane. The container's bottom is the plane from (0, `incline`) down to
    (`incline`, 0), then `floor` m of flat floor and a right wall; the left wall rises
    from the top of the plane; open top at `tank_height`. The drop's centre is above
    x = `impact_x`, so it touches the plane after t = sqrt(2 fall / g) (0.247 s by
    default) and slides down-slope (+x, -y).

    `dim` = 3 makes the drop a sphere and extrudes the geometry `depth` m along z,
    between two side walls `side_wall_height` m high above the bottom (the drop,
    centred in z, falls between them: the water spreads near the plane, so taller
    side walls would only add idle wall particles). Default dx: 0.01 m in 2D (1264
    fluid particles), 0.025 m in 3D (2176 fluid particles in the sphere).

    Physics and numerical defaults as ``dam_break``: h = 1.3 dx, alpha = 0.1,
    Lennard-Jones walls of particles dx/2 apart with r0 = dx/2 and D = 5 g H / r0, and
    c0 = 10 sqrt(2 g H), with H the height of the drop's top above the floor (the
    largest speed is that of a free fall from there). The drop starts at rho0: a body
    in free fall carries no hydrostatic pressure.

    `walls` = "dummy": dummy-particle walls instead (Adami et al. 2012, as ``dam_break``'s:
    ceil(support / dx) layers dx apart behind the container's outline, on each wall's own
    lattice so that the incline is smooth, :func:`taisph.geometry.container_layers`);
    the default with `solver` = "dfsph" (DFSPH's pressure solve needs walls of particles
    dx apart, and no Lennard-Jones force), else "lj". `solver` sets ``Scene.solver``.
    """
    walls = walls or ("dummy" if solver == "dfsph" else "lj")
    if solver == "dfsph" and walls == "lj":
        raise ParameterError("drop_on_incline: solver = 'dfsph' needs walls = 'dummy' (its pressure solve takes "
                             "the place of the Lennard-Jones wall force)")
    dx = (0.01 if dim == 2 else 0.025) if dx is None else dx
    width = incline + floor
    if not impact_x < incline:
        raise ParameterError(f"drop_on_incline: impact_x = {impact_x:g} m must lie over the inclined plane, "
                             f"0 < impact_x < incline = {incline:g} m")
    if not radius < impact_x or not impact_x + radius < width:
        raise ParameterError(f"drop_on_incline: the drop (radius = {radius:g} m around impact_x = {impact_x:g} m) "
                             f"must lie between the left wall (x = 0) and the right wall (x = incline + floor = "
                             f"{width:g} m)")
    if dim == 3 and not 2 * radius < depth:
        raise ParameterError(f"drop_on_incline: the sphere (radius = {radius:g} m) must fit between the side walls "
                             f"(depth = {depth:g} m)")
    # centre: touching the plane y = incline - x after falling `fall`
    centre_y = incline - impact_x + radius * SQRT2 + fall
    top = centre_y + radius
    if top + 2 * dx > tank_height:
        raise ParameterError(f"drop_on_incline: the drop (top at y = incline - impact_x + (1 + sqrt 2) radius + fall "
                             f"= {top:g} m, plus 2 dx) does not fit under tank_height = {tank_height:g} m")
    lattice_count("drop_on_incline", "the drop", dx, *[("radius", radius)] * dim)
    if dim == 3:  # the side walls are cut from a lattice over the container's side, dx/2 apart
        lattice_count("drop_on_incline", "the side walls", dx / 2, ("incline + floor", width),
                      ("tank_height", tank_height), spacing_name="dx/2")
    else:
        outline = 2 * tank_height + SQRT2 * incline + floor
        lattice_count("drop_on_incline", "the container's wall", dx / 2,
                      ("its length 2 tank_height + sqrt(2) incline + floor", outline), spacing_name="dx/2")
    c0 = sound_speed(g, top) if c0 is None else c0
    water = Material("water", rho0=1000.0, c0=c0, gamma=7.0)
    spacing = r0 = dx / 2.0
    gravity = (0.0, -g) if dim == 2 else (0.0, -g, 0.0)
    lo = [0.0, 0.0] + ([0.0] if dim == 3 else [])
    hi = [width, tank_height] + ([depth] if dim == 3 else [])
    dummy = walls == "dummy"
    wall_terms = ([AdamiWall()] if dummy else
                  [LennardJonesWall(lj_strength=lennard_jones_strength(g, top, r0), lj_cutoff=r0)])
    scene = Scene(
        name="drop_on_incline",
        dim=dim,
        dx=dx,
        smoothing_length=h_factor * dx,
        domain=(np.array(lo) - dx, np.array(hi) + dx),
        # the open top: a splash may fly above it and fall back; water leaving elsewhere (over a
        # wall) and, with WCSPH, the odd splash particle crushed out of the density range are
        # removed and counted, as in dam_break
        open_faces=("+y",),
        remove_escaped=True,
        materials=[water],
        terms=[
            Continuity(walls=dummy),
            PressureGradient(walls=dummy),
            ArtificialViscosity(alpha=alpha),
            Gravity(gravity=gravity),
            *wall_terms,
        ],
        solver=solver or "wcsph",
        kernel=kernel,
        integrator=integrator,
        t_end=t_end,
        frames=frames,
        description=(f"{'circular' if dim == 2 else 'spherical'} drop of radius {radius:g} m falling "
                     f"{fall:g} m onto a 45 deg plane"),
    )
    centre = [impact_x, centre_y] + ([0.5 * depth] if dim == 3 else [])
    scene.add_fluid(ball(centre, radius, dx))
    outline = [(0.0, tank_height), (0.0, incline), (incline, 0.0), (width, 0.0), (width, tank_height)]
    if dummy:
        layers = support_layers(scene.support_radius, dx)
        scene.domain = (np.array(lo) - (layers + 1) * dx, np.array(hi) + (layers + 1) * dx)
        layer_points = container_layers(outline, dx, layers)
        if dim == 2:
            scene.add_walls(layer_points)
        else:
            z = (np.arange(-layers, math.ceil(depth / dx - 1e-9) + layers) + 0.5) * dx
            extruded = np.concatenate([np.column_stack([layer_points, np.full(len(layer_points), zk)]) for zk in z])
            xs = (np.arange(math.ceil(width / dx - 1e-9)) + 0.5) * dx
            ys = (np.arange(math.ceil(tank_height / dx - 1e-9)) + 0.5) * dx
            x, y = (m.ravel() for m in np.meshgrid(xs, ys, indexing="ij"))
            bottom = np.maximum(incline - x, 0.0)
            keep = (y > bottom) & (y < bottom + side_wall_height)
            face = np.column_stack([x[keep], y[keep]])
            sides = [np.column_stack([face, np.full(len(face), zk)])
                     for k in range(layers) for zk in (-(k + 0.5) * dx, depth + (k + 0.5) * dx)]
            scene.add_walls(np.concatenate([extruded, *sides]))
        return scene
    profile = polyline(outline, spacing)
    if dim == 2:
        scene.add_walls(profile)
    else:
        def above_bottom(x, y):
            bottom = np.maximum(incline - x, 0.0)
            return ((y > bottom + 0.5 * spacing) & (y < bottom + side_wall_height)
                    & (x > 0.5 * spacing) & (x < width - 0.5 * spacing))

        walls = np.concatenate([extrude(profile, depth, spacing),
                                side_walls(above_bottom, (0.0, 0.0), (width, tank_height), depth, spacing)])
        scene.add_walls(walls)
    return scene


def downslope(points) -> np.ndarray:
    """Coordinate along the plane, increasing down-slope (direction (1, -1)/sqrt 2)."""
    points = np.asarray(points, float)
    return (points[..., 0] - points[..., 1]) / SQRT2


def height_above_plane(points, incline: float = 1.6) -> np.ndarray:
    """Signed distance of points above the plane x + y = incline (positive above)."""
    points = np.asarray(points, float)
    return (points[..., 0] + points[..., 1] - incline) / SQRT2
