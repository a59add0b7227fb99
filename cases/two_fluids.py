"""Two fluids of density ratio 2 in a box, the heavy one on top: a Rayleigh-Taylor instability (seed Figure 4)."""

import numpy as np

from taisph.scene import Material, Scene
from taisph.geometry import box_walls, lattice, support_layers, wall_layers
from taisph.terms import (STANDARD_GRAVITY, ArtificialViscosity, ContinuityColagrossi, Gravity, LennardJonesWall,
                          PressureHuAdams)
from taisph.eos import tait
from taisph.scene.water import lennard_jones_strength, sound_speed
from taisph.scene.parameters import (ParameterError, at_least, checked, end_time, frame_count, gravity_magnitude,
                                     known_integrator, known_kernel, lattice_count, one_of, optional, positive,
                                     smoothing_factor, speed_of_sound, viscosity_alpha)
from taisph.scene.phases import two_phase_terms


@checked(dx=positive, width=positive, height=positive, tank_height=positive, density_ratio=positive,
         upper_density=positive, amplitude=at_least(0), alpha=viscosity_alpha, c0=optional(speed_of_sound),
         lower_c0=optional(speed_of_sound), h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel,
         integrator=known_integrator, t_end=end_time, frames=frame_count, walls=one_of("lj", "dummy"),
         background_pressure=at_least(0))
def two_fluids(
    dx: float = 0.02,
    width: float = 1.0,
    height: float = 2.0,
    tank_height: float = 2.5,
    density_ratio: float = 2.0,
    upper_density: float = 1000.0,
    amplitude: float = 0.05,
    alpha: float = 0.1,
    c0: float | None = None,
    lower_c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 2.5,
    frames: int = 25,
    walls: str = "lj",
    background_pressure: float = 0.0,
) -> Scene:
    """A `width` x `height` box of liquid, open at the top (walls up to
    `tank_height`): the upper half is fluid of `upper_density` (material 0), the lower
    half `upper_density` / `density_ratio` (material 1). The default ratio 2 puts the
    heavy fluid on top, half as dense below (the seed's Figure 4); a ratio below 1 is
    the stable stratification (the tests' control). The interface is
    y = height/2 + `amplitude` cos(2 pi x / width): the upper fluid reaches lowest at
    mid-width, where its finger falls; light fluid rises along the side walls. Linear
    theory (inviscid): the perturbation grows as cosh(sigma t), sigma = sqrt(A k g)
    with the Atwood number A = (r - 1)/(r + 1) = 1/3 and k = 2 pi / width, so
    sigma = 4.5 / s by default.

    Formulation (sharp interface): momentum after Hu & Adams (2006) and continuity
    after Colagrossi & Landrini (2003), both using each particle's own density and
    volume (``terms/pressure_hu_adams.py``, ``terms/continuity_colagrossi.py``),
    Tait equation of state per material with its own rho0 and c0 = 10 sqrt(2 g H)
    (`lower_c0`, default the same c0, sets the lower fluid's: c0 sqrt(density_ratio)
    gives both fluids the same stiffness B = rho0 c0^2 / gamma, which large density
    ratios need, docs/stability.md), Monaghan viscosity alpha = 0.1, gravity, Lennard-Jones walls as in
    ``dam_break`` (particles dx/2 apart, r0 = dx/2, D = 5 g H / r0), h = 1.3 dx.
    Each particle's mass is its material's rho0 dx^2; the initial density is
    hydrostatic (the pressure of the fluid above, through each material's inverse
    Tait). Default dx = 0.02 m: 5000 fluid particles.

    ``walls="dummy"`` with a `background_pressure` (Pa, both materials) and `lower_c0`
    = c0 sqrt(density_ratio) (the same stiffness) is the formulation for large density
    ratios (docs/multiphase.md): dummy walls (Adami et al. 2012) whose pressure each
    phase reads through its own equation of state, instead of Lennard-Jones walls; it
    holds ratio 100 in a full box (`height` = `tank_height`, closed at the top;
    tests/test_stability.py). A background pressure needs the box full: at a free
    surface it would push the particles apart.
    """
    if not amplitude < 0.25 * height:
        raise ParameterError(f"two_fluids: amplitude must be below height/4 = {0.25 * height:g} m (the interface "
                             f"stays inside the box), got {amplitude!r}")
    if height > tank_height:
        raise ParameterError(f"two_fluids: the liquid (height = {height:g} m) must fit under the walls "
                             f"(tank_height = {tank_height:g} m)")
    lattice_count("two_fluids", "the liquid", dx, ("width", width), ("height", height))
    lattice_count("two_fluids", "the tank", dx, ("width", width), ("tank_height", tank_height))
    c0 = sound_speed(g, height) if c0 is None else c0
    upper = Material("upper", rho0=upper_density, c0=c0, gamma=7.0, background_pressure=background_pressure)
    lower_c0 = c0 if lower_c0 is None else lower_c0
    lower = Material("lower", rho0=upper_density / density_ratio, c0=lower_c0, gamma=7.0,
                     background_pressure=background_pressure)
    spacing = r0 = dx / 2.0 if walls == "lj" else dx
    scene = Scene(
        name="two_fluids",
        dim=2,
        dx=dx,
        smoothing_length=h_factor * dx,
        domain=(np.array([-dx, -dx]), np.array([width + dx, tank_height + dx])),
        materials=[upper, lower],
        terms=[
            ContinuityColagrossi(),
            PressureHuAdams(),
            ArtificialViscosity(alpha=alpha),
            Gravity(gravity=(0.0, -g)),
            LennardJonesWall(lj_strength=lennard_jones_strength(g, height, r0), lj_cutoff=r0),
        ] if walls == "lj" else [*two_phase_terms(walls=True, gravity=(0.0, -g), viscous=False),
                                 ArtificialViscosity(alpha=alpha, walls=True)],
        kernel=kernel,
        integrator=integrator,
        t_end=t_end,
        frames=frames,
        description=(f"{upper.rho0:g} kg/m^3 fluid over {lower.rho0:g} kg/m^3 fluid in a {width:g} m x "
                     f"{height:g} m box (Rayleigh-Taylor, Hu & Adams / Colagrossi & Landrini multiphase form)"),
    )
    points = lattice([0.0, 0.0], [width, height], dx)
    x, y = points[:, 0], points[:, 1]
    interface = interface_height(x, width, height, amplitude)
    is_upper = y > interface
    # hydrostatic pressure: the upper column above, plus the lower column for lower particles
    p = background_pressure + np.where(is_upper, upper.rho0 * g * (height - y),
                                       upper.rho0 * g * (height - interface) + lower.rho0 * g * (interface - y))
    for k, (material, sel) in enumerate(((upper, is_upper), (lower, ~is_upper))):
        rho = tait.density(p[sel], material.rho0, material.c0, material.gamma, background_pressure)
        scene.add_fluid(points[sel], material=k, density=rho, mass=material.rho0 * dx**2)
    if walls == "lj":
        scene.add_walls(box_walls([0.0, 0.0], [width, tank_height], spacing))
    else:  # layers of dummy particles filling a kernel support outside the box
        layers = support_layers(scene.support_radius, dx)
        closed = height == tank_height  # a full box: closed at the top
        scene.add_walls(wall_layers([0.0, 0.0], [width, tank_height], dx, layers, open_top=not closed))
        pad = (layers + 1) * dx
        scene.domain = (np.array([-pad, -pad]), np.array([width + pad, tank_height + (pad if closed else dx)]))
    return scene


def interface_height(x, width=1.0, height=2.0, amplitude=0.05):
    """The initial interface y(x) between the upper and the lower fluid."""
    return 0.5 * height + amplitude * np.cos(2.0 * np.pi * np.asarray(x, float) / width)
