"""3D dam break: a water column collapses in a narrow tank (x along the flow, y up, z across)."""

from taisph.scene.parameters import (checked, courant_number, diffusion_delta, end_time, flag, frame_count,
                                     gravity_magnitude, known_integrator, known_kernel, one_of, optional, positive,
                                     smoothing_factor, speed_of_sound, viscosity_alpha, xsph_epsilon)

from taisph.scene.names import FORMULATIONS
from taisph.terms import STANDARD_GRAVITY

from .dam_break import WALL_MODELS, _dam_break, headline  # noqa: F401 (its headline results: the 2D case's)


@checked(dx=positive, width=positive, height=positive, depth=positive, tank_width=positive, tank_height=positive,
         alpha=viscosity_alpha, c0=optional(speed_of_sound), h_factor=smoothing_factor, g=gravity_magnitude,
         kernel=known_kernel, integrator=known_integrator, seed_physics=flag, walls=optional(one_of(*WALL_MODELS)),
         wall_friction=optional(flag), delta=optional(diffusion_delta), xsph=optional(xsph_epsilon),
         courant=optional(courant_number), tension=flag, t_end=end_time, frames=frame_count, closed_top=flag,
         formulation=one_of(*FORMULATIONS))
def dam_break_3d(
    dx: float = 0.05,
    width: float = 1.0,
    height: float = 2.0,
    depth: float = 1.0,
    tank_width: float = 4.0,
    tank_height: float = 3.0,
    alpha: float = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    seed_physics: bool = False,
    walls: str | None = None,
    wall_friction: bool | None = None,
    delta: float | None = None,
    xsph: float | None = None,
    courant: float | None = None,
    tension: bool = True,
    t_end: float = 1.0,
    frames: int = 25,
    closed_top: bool = False,
    formulation: str = "symmetric",
):
    """The 2D dam break extruded to `depth` (m) between two side walls.

    Defaults: 1 x 2 x 1 m column in a 4 x 3 x 1 m tank, dx = 0.05 m (16000 fluid
    particles), same physics, options and defaults as ``dam_break``.
    """
    return _dam_break(3, dx, width, height, depth, tank_width, tank_height, alpha, c0, h_factor, g,
                      kernel, integrator, t_end, frames, "dam_break_3d", seed_physics=seed_physics, walls=walls,
                      wall_friction=wall_friction, delta=delta, xsph=xsph, courant=courant, tension=tension,
                      closed_top=closed_top, formulation=formulation)
