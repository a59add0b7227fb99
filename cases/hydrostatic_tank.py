"""Hydrostatic tank: still water in an open-topped tank must stay still, with p = rho g (H - y) (Adami, Hu & Adams 2012, sec. 6)."""

from taisph.scene.parameters import (checked, diffusion_delta, end_time, flag, frame_count, gravity_magnitude,
                                     known_integrator, known_kernel, lattice_count, one_of, optional, positive,
                                     smoothing_factor, speed_of_sound, viscosity_alpha)
from taisph.terms import STANDARD_GRAVITY

from .dam_break import WALL_MODELS, _dam_break


@checked(dx=positive, width=positive, height=positive, alpha=viscosity_alpha, c0=optional(speed_of_sound),
         h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel, integrator=known_integrator,
         walls=one_of(*WALL_MODELS), wall_friction=flag, delta=optional(diffusion_delta), t_end=end_time,
         frames=frame_count)
def hydrostatic_tank(
    dx: float = 0.025,
    width: float = 1.0,
    height: float = 0.5,
    alpha: float = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    walls: str = "dummy",
    wall_friction: bool = False,
    delta: float | None = 0.1,
    t_end: float = 2.0,
    frames: int = 20,
):
    """A `width` x `height` (m) body of water filling the bottom of a tank of the same
    width, starting in hydrostatic equilibrium (inverse Tait density). Nothing should
    move: the pressure should stay rho g (H - y), the surface flat, the walls tight.

    Defaults: 1 m x 0.5 m, dx = 0.025 m (800 particles), c0 = 10 sqrt(2 g H), alpha =
    0.1, dummy walls (walls="dummy"; "lj" gives the seed's Lennard-Jones walls),
    2 s (about 120 acoustic periods H/c0). delta: density diffusion coefficient
    (with the hydrostatic correction), 0.1 by default, 0 or None for none: without it a
    zig-zag pressure mode of the particle row on the floor grows after a few seconds
    (docs/accuracy.md, "Still water").
    """
    lattice_count("hydrostatic_tank", "the tank", dx, ("width", width), ("1.5 height", 1.5 * height))
    return _dam_break(2, dx, width, height, None, width, 1.5 * height, alpha, c0, h_factor, g, kernel, integrator,
                      t_end, frames, "hydrostatic_tank", walls=walls, wall_friction=wall_friction, delta=delta or 0.0,
                      description=f"{width:g} m x {height:g} m of still water in an open-topped tank "
                                  "(walls on three sides)")


def headline(sim, out) -> list:
    """At the end: the mean pressure of the fluid's bottom row (Pa) against rho0 g (H - y)
    there, and the rms of p - rho0 g (H - y) over rho0 g H, over the fluid deeper than a
    kernel support (as taisph.validation.runs.hydrostatic_tank measures it at each sample)."""
    import numpy as np

    from taisph.run.results import Result

    p, scene = sim.scene.case_parameters, sim.scene
    rho0, g, H = scene.materials[0].rho0, p["g"], p["height"]
    x, pressure = sim.positions()[sim.fluid], sim.pressure()[sim.fluid]
    exact = rho0 * g * (H - x[:, 1])
    bottom = x[:, 1] < x[:, 1].min() + 0.5 * scene.dx
    deep = x[:, 1] < H - scene.support_radius
    rms = float(np.sqrt(np.mean((pressure[deep] - exact[deep]) ** 2)) / (rho0 * g * H)) if deep.any() else np.nan
    at = f"at t = {sim.time:.3g} s"
    return [Result("p_bottom", float(pressure[bottom].mean()), "Pa", float(exact[bottom].mean()),
                   "hydrostatic rho0 g (H - y)", f"mean over the fluid's bottom row, {at}"),
            Result("p_rms_error", rms, "1", None, "",
                   f"rms of p - rho0 g (H - y) over rho0 g H, deeper than a kernel support, {at}")]
