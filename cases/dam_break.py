"""2D dam break: a water column collapses in a tank (Martin & Moyce 1952; Koshizuka & Oka 1996)."""

import math

import numpy as np

from taisph.scene import Material, Scene
from taisph.geometry import box_walls, lattice, support_layers, wall_layers
from taisph.scene.names import FORMULATIONS, UP
from taisph.scene.parameters import (ParameterError, between, checked, courant_number, diffusion_delta, end_time, flag,
                                     frame_count, gravity_magnitude, known_integrator, known_kernel, lattice_count,
                                     one_of, optional, positive, smoothing_factor, speed_of_sound, viscosity_alpha,
                                     xsph_epsilon)
from taisph.scene.water import hydrostatic_density, lennard_jones_strength, sound_speed
from taisph.terms import (STANDARD_GRAVITY, XSPH, AdamiWall, ArtificialViscosity, Continuity, DensityDiffusion, Gravity,
                          LennardJonesWall, ParticleShifting, PressureGradient, Riemann)
from taisph.eos import Tait

WALL_MODELS = ("lj", "dummy")


@checked(dx=positive, width=positive, height=positive, tank_width=positive, tank_height=positive,
         alpha=viscosity_alpha, c0=optional(speed_of_sound), h_factor=smoothing_factor, g=gravity_magnitude,
         kernel=known_kernel, integrator=known_integrator, seed_physics=flag, walls=optional(one_of(*WALL_MODELS)),
         wall_friction=optional(flag), delta=optional(diffusion_delta), xsph=optional(xsph_epsilon),
         courant=optional(courant_number), tension=flag, t_end=end_time, frames=frame_count, closed_top=flag,
         formulation=one_of(*FORMULATIONS), shifting=between(0, 1000))
def dam_break(
    dx: float = 0.02,
    width: float = 1.0,
    height: float = 2.0,
    tank_width: float = 4.0,
    tank_height: float = 4.0,
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
    t_end: float = 2.0,
    frames: int = 50,
    closed_top: bool = False,
    formulation: str = "symmetric",
    shifting: float = 0.0,
) -> Scene:
    """Water column `width` x `height` (m) at the left wall of a `tank_width` tank.

    Defaults: 1 m x 2 m column, 4 m tank, dx = 0.02 m (5000 fluid particles), cubic
    spline with h = 1.3 dx, predictor-corrector, Monaghan viscosity alpha = 0.1, Tait
    water with c0 = 10 sqrt(2 g H) (about 10x the largest flow speed), and the most
    accurate physics per unit of wall time of the study python -m
    tools.studies.dam_break_defaults: dummy walls (three layers dx apart, pressure
    extrapolated from the fluid, Adami et al. 2012) with wall friction, density diffusion
    delta = 0.1, and an adaptive step with Courant number 0.4 in 2D and 0.3 in 3D, the
    largest that keep the fluid's particles to t = 3 s (docs/stability.md, "Time step").
    The pressure noise and surge front this gives, against the seed's physics:
    docs/performance.md, "The flagship's physics". The column starts in hydrostatic
    equilibrium (inverse Tait).

    seed_physics: the seed report's model instead: Lennard-Jones walls (seed eq. 13) of
    particles dx/2 apart with r0 = dx/2 and D = 5 g H / r0, no density diffusion, no
    wall friction, Courant number 0.25.
    The tank is open at the top unless `closed_top`: water may run up a wall, fly
    above the domain and fall back (the top is not a guard), and water that goes over
    a wall and leaves the domain elsewhere is removed and counted, as are particles
    whose density leaves the guard's range, up to the max_out_of_range control (the
    run summary accounts for their mass; docs/stability.md).

    tension: True (default, also with the seed's physics), the Tait equation as it is
    (negative pressure in a stretched fluid); False, ``Tait(tension=False)``: density
    held at >= rho0, so pressure >= 0 (a liquid that cannot be stretched;
    docs/stability.md).

    Each of the following, left at None, follows the model (the defaults above, or
    the seed's): walls "dummy" or "lj"; wall_friction (dummy walls only): artificial
    viscosity also between fluid and wall particles with the no-slip wall velocity, a
    numerical friction that slows the front and holds water on the back wall
    (docs/accuracy.md); delta: the density diffusion coefficient (0: none); courant:
    the adaptive step's Courant number (with dummy walls and density diffusion 0.4 in
    2D and 0.3 in 3D, else the engine's 0.25). xsph: XSPH epsilon, 0 or None for none.

    formulation: "symmetric" (default), the continuity and momentum equations of the seed
    (eqs. 7-8); "riemann", the Riemann-solver formulation of Zhang, Hu & Adams (2017;
    ``taisph.terms.Riemann``, the scene files' default for one fluid under WCSPH): a smoother
    wall pressure at the same front on the Buchner dam break (docs/validation.md, "What sets
    the wall pressure"), at a higher cost per step, and with the engine's Courant number
    0.25 (the symmetric form's 0.4 does not hold with it). This case keeps the symmetric form
    and the wall friction by default: on Buchner's sensors formulation="riemann" with
    wall_friction=False gives a truer wall pressure and impact time, and a front nearer a
    fine solution's, but Koshizuka & Oka's front farther, at a few times the wall time
    (docs/validation.md, "The Riemann formulation", for the figures): use those two
    settings for wall loads.

    shifting: particle shifting's reference speed U (m/s; 0, the default: none), with the
    free-surface rule (``taisph.terms.ParticleShifting(free_surface=True)``); with density
    diffusion it makes Sun et al.'s (2017) delta-plus-SPH; about sqrt(2 g H) (6.3 m/s for
    the default column); it needs wall_friction=False (refused with the wall friction:
    particle_shifting.py says why). Measured in docs/validation.md.
    """
    return _dam_break(2, dx, width, height, None, tank_width, tank_height, alpha, c0, h_factor, g,
                      kernel, integrator, t_end, frames, "dam_break", seed_physics=seed_physics, walls=walls,
                      wall_friction=wall_friction, delta=delta, xsph=xsph, courant=courant, tension=tension,
                      closed_top=closed_top, formulation=formulation, shifting=shifting)


def physics(seed_physics=False, walls=None, wall_friction=None, delta=None, courant=None, dim=2,
            formulation="symmetric"):
    """The dam break's model settings with the Nones filled in (see dam_break)."""
    walls = walls or ("lj" if seed_physics else "dummy")
    if wall_friction is None:
        wall_friction = walls == "dummy" and not seed_physics
    if delta is None:
        delta = 0.0 if seed_physics else 0.1
    # the Courant numbers 0.4 / 0.3 hold with the symmetric form; the Riemann formulation
    # keeps the engine's 0.25 (docs/validation.md, "The Riemann formulation")
    if courant is None and walls == "dummy" and delta and formulation == "symmetric":
        courant = 0.4 if dim == 2 else 0.3
    return walls, wall_friction, delta, courant


def _dam_break(dim, dx, width, height, depth, tank_width, tank_height, alpha, c0, h_factor, g,
               kernel, integrator, t_end, frames, name, seed_physics=False, walls=None, wall_friction=None,
               delta=None, xsph=None, courant=None, description=None, closed_top=False, tension=True,
               formulation="symmetric", shifting=0.0):
    walls, wall_friction, delta, courant = physics(seed_physics, walls, wall_friction, delta, courant, dim,
                                                   formulation)
    if shifting and wall_friction:
        raise ParameterError(f"{name}: shifting with wall_friction holds a film of water on the back wall (the "
                             "residual column 0.93 high at t sqrt(g/L) = 2.2 against 0.54 without shifting at "
                             "dx = 0.02; "
                             "taisph/terms/particle_shifting.py): set wall_friction=False with shifting")
    if wall_friction and walls != "dummy":
        raise ParameterError(f"{name}: wall_friction needs walls = 'dummy' (the Lennard-Jones walls carry no "
                             "velocity to rub against)")
    # what the ranges of single parameters cannot say (they are checked by each case's @checked)
    if width > tank_width or height > tank_height:
        raise ParameterError(f"{name}: the water column (width = {width:g} m, height = {height:g} m) must fit in "
                             f"the tank (tank_width = {tank_width:g} m, tank_height = {tank_height:g} m)")
    sides = [("width", width), ("height", height)] + ([("depth", depth)] if dim == 3 else [])
    lattice_count(name, "the water column", dx, *sides)
    # the tank's walls are cut from a lattice over the whole tank (geometry.box_walls), as
    # much memory as the tank filled at dx
    lattice_count(name, "the tank", dx, ("tank_width", tank_width), ("tank_height", tank_height),
                  *([("depth", depth)] if dim == 3 else []))
    c0 = sound_speed(g, height) if c0 is None else c0
    water = Material("water", rho0=1000.0, c0=c0, gamma=7.0)
    eos = Tait(tension=tension)
    gravity = [0.0] * dim  # y up in 2D and in 3D (x along the flow, z across in 3D)
    gravity[UP] = -g
    dummy = walls == "dummy"
    # the continuity and momentum equations: the seed's symmetric form or the Riemann solver's
    equations = [Riemann(walls=dummy)] if formulation == "riemann" else [Continuity(walls=dummy),
                                                                          PressureGradient(walls=dummy)]
    terms = [
        *equations,
        ArtificialViscosity(alpha=alpha, walls=dummy and wall_friction),
        Gravity(gravity=tuple(gravity)),
    ]
    if dummy:
        terms.append(AdamiWall())
    else:
        r0 = dx / 2.0
        terms.append(LennardJonesWall(lj_strength=lennard_jones_strength(g, height, r0), lj_cutoff=r0))
    if delta:  # None or 0: no term
        terms.append(DensityDiffusion(delta=delta))
    if xsph:  # None or 0: no term
        terms.append(XSPH(xsph_eps=xsph))
    if shifting:  # 0: no term; delta-SPH with this shifting is Sun et al.'s (2017) delta-plus-SPH
        terms.append(ParticleShifting(shift_speed=shifting, free_surface=True))
    column_hi = [width, height] + ([depth] if dim == 3 else [])  # x along the flow, y up, z across
    tank_hi = [tank_width, tank_height] + ([depth] if dim == 3 else [])
    lo = [0.0] * dim
    h = h_factor * dx
    scene = Scene(
        name=name,
        dim=dim,
        dx=dx,
        smoothing_length=h,
        # the neighbour grid covers the tank and a margin above it; particles beyond are
        # still simulated exactly (only more slowly)
        domain=(np.array(lo) - dx, np.array(tank_hi) + dx + np.eye(dim)[UP] * 0.5 * tank_height),
        open_faces=() if closed_top else ("+y",),
        remove_escaped=True,
        courant=courant,
        materials=[water],
        eos=eos,
        terms=terms,
        kernel=kernel,
        integrator=integrator,
        t_end=t_end,
        frames=frames,
        description=description or f"{width:g} m x {height:g} m water column collapsing in a {tank_width:g} m tank",
    )
    fluid = lattice(lo, column_hi, dx)
    scene.add_fluid(fluid, density=hydrostatic_density(water, g, height - fluid[:, UP]))
    if dummy:
        layers = support_layers(scene.support_radius, dx)
        pad = layers * dx
        top = np.eye(dim)[UP] * (0.5 * tank_height if not closed_top else 0.0)
        scene.domain = (np.array(lo) - pad - dx, np.array(tank_hi) + pad + dx + top)
        scene.add_walls(wall_layers(lo, tank_hi, dx, layers, vertical_axis=UP, open_top=not closed_top))
    else:
        scene.add_walls(box_walls(lo, tank_hi, dx / 2.0, vertical_axis=UP, open_top=not closed_top))
    return scene


def headline(sim, out) -> list:
    """The surge front Z = x_front / width and the residual column height H = h / height at
    the end (x_front the largest fluid x plus dx/2; h the highest fluid y plus dx/2 within
    0.1 width of the back wall), against Martin & Moyce's (1952) tables at the same
    dimensionless time T = t sqrt(2 g / width) (front), tau = t sqrt(g / width) (height),
    as taisph.validation.runs.dam_break reads them: a reference only for their column
    (height = 2 width), within the tables' times, and for the front before it reaches the
    far wall."""
    from taisph.run.results import Result
    from taisph.validation.runs import reference

    p, dx, t = sim.scene.case_parameters, sim.scene.dx, sim.time
    width, height, g = p["width"], p["height"], p["g"]
    x = sim.positions()[sim.fluid]
    front = (x[:, 0].max() + dx / 2) / width
    near = x[:, 0] < 0.1 * width
    column = (x[near, UP].max() + dx / 2) / height if near.any() else 0.0
    source, results = "Martin & Moyce (1952)", []
    for name, value, table, time, what in (
            ("front", front, "martin_moyce_1952_surge_front_table.csv", t * math.sqrt(2 * g / width),
             "x_front / width at T = t sqrt(2 g / width) = "),
            ("column_height", column, "martin_moyce_1952_column_height_table.csv", t * math.sqrt(g / width),
             "h / height at tau = t sqrt(g / width) = ")):
        data = reference(table)[0]
        within = math.isclose(height, 2 * width) and data[0, 0] <= time <= data[-1, 0]
        if name == "front" and front * width >= p["tank_width"] - 2 * dx:
            within, what = False, "the front has reached the far wall; " + what
        results.append(Result(name, float(value), "1", float(np.interp(time, data[:, 0], data[:, 1])) if within
                              else None, source if within else "", f"{what}{time:.3g}"))
    return results
