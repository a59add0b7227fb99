"""Floating box at rest: a 2D box half as dense as water floats in still water with half its
height submerged (Archimedes), its weight carried by the fluid's pressure."""

import numpy as np

from taisph.scene.parameters import (ParameterError, checked, end_time, frame_count, gravity_magnitude,
                                     known_integrator,
                                     known_kernel, lattice_count, one_of, optional, positive, smoothing_factor,
                                     speed_of_sound, viscosity_alpha)
from taisph.geometry import lattice
from taisph.probes import body, elevation
from taisph.scene.names import UP
from taisph.terms import STANDARD_GRAVITY

from .dam_break import _dam_break

RHO_WATER = 1000.0


@checked(dim=one_of(2, 3), dx=positive, tank_width=positive, depth=positive, box_width=positive, box_height=positive,
         box_density=positive, box_bottom=optional(positive), alpha=viscosity_alpha, c0=optional(speed_of_sound),
         h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel, integrator=known_integrator,
         t_end=end_time, frames=frame_count)
def floating_box(
    dim: int = 2,
    dx: float = 0.02,
    tank_width: float = 1.5,
    depth: float = 1.0,
    box_width: float = 0.5,
    box_height: float = 0.5,
    box_density: float = 500.0,
    box_bottom: float | None = None,
    alpha: float = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 3.0,
    frames: int = 30,
):
    """A `box_width` x `box_height` box of density `box_density` floating in a
    `tank_width` tank of still water `depth` deep (defaults: 0.5 m x 0.5 m, 500 kg/m^3,
    1.5 m x 1 m of water, dx = 0.02 m: 3450 fluid and 625 body particles).

    The box starts in the middle of the tank (off it by dx/2 if the tank's and the box's
    widths in dx differ in parity) at its equilibrium draft, box_density / 1000 x
    box_height (0.25 m), rounded to the lattice (within dx/2), or with its bottom at
    `box_bottom` (m above the floor: e.g. a submerged, neutrally buoyant box), with no
    fluid in its volume; the water is hydrostatic. The upright square of half the water's
    density is statically unstable (metacentric height b^2 / (12 d) - (b - d) / 2 =
    -0.042 m): symmetric, it stays upright only while its roll, grown from round-off,
    is small (docs/bodies.md). Floating (:meth:`taisph.Scene.add_body`): mass and inertia from its
    particles, the dam break's physics otherwise (dummy walls with friction, density
    diffusion delta = 0.1, Monaghan alpha = 0.1, c0 = 10 sqrt(2 g depth)).

    Probes (``python -m taisph floating_box`` writes OUT/probes.csv): the body probe
    ``box`` every 10 steps (``box_x``, ``box_y``: centre of mass; ``box_angle``, rad;
    velocities and the fluid's force) and the wave gauge ``gauge`` at x = 0.15 tank_width,
    away from the box, so that the draft is ``gauge - (box_y - box_height / 2)``.
    """
    if box_width >= tank_width:
        raise ParameterError(f"floating_box: the box (box_width = {box_width:g} m) must be narrower than the tank "
                             f"(tank_width = {tank_width:g} m)")
    draft = box_density / RHO_WATER * box_height if box_bottom is None else depth - box_bottom
    if draft >= depth or draft <= 0.0:
        raise ParameterError(f"floating_box: the box's draft ({draft:g} m: box_density / 1000 x box_height, or "
                             f"depth - box_bottom) must be between 0 and the water's depth ({depth:g} m)")
    lattice_count("floating_box", "the box", dx, ("box_width", box_width), ("box_height", box_height))
    lattice_count("floating_box", "the tank", dx, ("tank_width", tank_width), ("depth", depth))
    across = tank_width if dim == 3 else None  # 3D: a square tank, a cube (box_width across)
    scene = _dam_break(dim, dx, tank_width, depth, across, tank_width, depth + box_height + 0.5, alpha, c0,
                       h_factor, g, kernel, integrator, t_end, frames, "floating_box",
                       description=f"{box_width:g} m x {box_height:g} m box of {box_density:g} kg/m^3 floating in "
                                   f"{depth:g} m of still water")
    # the box's lattice continues the fluid's (corners on multiples of dx), at its draft
    lo = np.array([round((tank_width - box_width) / 2 / dx), round((depth - draft) / dx)]
                  + [round((tank_width - box_width) / 2 / dx)] * (dim - 2)) * dx
    hi = lo + np.array([round(box_width / dx), round(box_height / dx)] + [round(box_width / dx)] * (dim - 2)) * dx
    inside = np.all((scene.position > lo) & (scene.position < hi), axis=1) & (scene.kind == 0)
    _drop(scene, inside)
    scene.add_body("box", lattice(lo, hi, dx), density=box_density)
    gauge = (0.15 * tank_width,) + (0.5 * tank_width,) * (dim - 2)
    scene.probes += [body("box", every=10), elevation("gauge", at=gauge)]
    assert UP == 1
    return scene


def _drop(scene, mask):
    """Remove the particles of `mask` from `scene` (before any body or term refers to them)."""
    keep = ~mask
    for key in ("position", "velocity", "mass", "density", "kind", "material"):
        setattr(scene, key, getattr(scene, key)[keep])
    for key, values in scene.quantities.items():
        scene.quantities[key] = np.asarray(values)[keep]


def headline(sim, out) -> list:
    """The box's draft at the end, the water level at the gauge (away from the box) less the
    height of the box's bottom (its centre of mass minus box_height / 2; upright), against
    Archimedes' box_density / 1000 x box_height."""
    from taisph.run.results import Result, sample_probes

    p = sim.scene.case_parameters
    level = sample_probes(sim, [q for q in sim.scene.probes if q.name == "gauge"])["gauge"]
    bottom = float(sim.bodies()["box"].position[UP]) - 0.5 * p["box_height"]
    floats = p["box_density"] < RHO_WATER
    return [Result("draft", level - bottom, "m", p["box_density"] / RHO_WATER * p["box_height"] if floats else None,
                   "Archimedes" if floats else "",
                   f"water level at the gauge less the box's bottom, at t = {sim.time:.3g} s")]
