"""Laminar flow past a cylinder in a channel: the DFG benchmark 2D-1 (Re 20) and 2D-2 (Re 100) of Schäfer & Turek (1996)."""

import math

import numpy as np

from taisph.geometry import lattice, support_layers
from taisph.probes import force, pressure
from taisph.scene import Material, Scene
from taisph.scene.parameters import (ParameterError, at_least, between, checked, end_time, flag, frame_count, integer,
                                     known_integrator, known_kernel, one_of, optional, positive, smoothing_factor)
from taisph.terms import (AdamiWall, Continuity, DensityDiffusion, LaminarViscosity, ParticleShifting, PressureGradient,
                          SummationDensity)

# the benchmark's geometry (m) and fluid (Schaefer & Turek 1996, sec. 2)
LENGTH, HEIGHT = 2.2, 0.41
CENTRE, DIAMETER = (0.2, 0.2), 0.1
NU, RHO = 1e-3, 1.0
# their reference values for Re = 20 (2D-1, steady): drag and lift coefficients, p(front) - p(back) (Pa)
REFERENCE_RE20 = {"C_D": 5.5795, "C_L": 0.0106, "dp": 0.1175}
BACKGROUND = 0.3 / 0.3**2  # the default background pressure over rho U_max^2: 0.3 Pa at Re 20


@checked(dx=positive, re=between(1, 200), c0=optional(positive), p_background=optional(at_least(0)), ramp=at_least(0),
         h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator, delta=at_least(0), shifting=flag,
         every=integer(at_least=1), surface=one_of("lattice", "rings"), density=one_of("continuity", "summation"),
         t_end=end_time, frames=frame_count)
def cylinder(
    dx: float = 0.005,
    re: float = 20.0,
    c0: float | None = None,
    p_background: float | None = None,
    ramp: float = 1.0,
    h_factor: float = 1.3,
    kernel: str = "wendland",
    integrator: str = "pc",
    delta: float = 0.1,
    shifting: bool = True,
    every: int = 10,
    surface: str = "rings",
    density: str = "summation",
    t_end: float = 8.0,
    frames: int = 16,
) -> Scene:
    """Flow past a circular cylinder in a channel, the DFG benchmark of Schaefer & Turek
    (1996, "Benchmark computations of laminar flow around a cylinder", Notes Numer.
    Fluid Mech. 52:547): a channel 2.2 m x 0.41 m with no-slip walls at y = 0 and
    y = 0.41, a cylinder of diameter D = 0.1 m centred at (0.2, 0.2) (slightly below
    the middle: a small lift), nu = 1e-3 m^2/s, rho = 1, no gravity. Inflow at x = 0:
    the parabola u(y) = 4 U_max y (H - y) / H^2 with U_max = 1.5 re nu / D, so that the
    mean speed U = 2/3 U_max makes Re = U D / nu (re = 20: U_max = 0.3 m/s, the steady
    case 2D-1; re = 100: 1.5 m/s, vortex shedding, 2D-2). Outflow at x = 2.2: p = 0,
    velocity extrapolated (taisph.terms.open_boundary). References for re = 20:
    C_D = 2 F_x / (rho U^2 D) = 5.5795, C_L = 2 F_y / (rho U^2 D) = 0.0106 and
    p(0.15, 0.2) - p(0.25, 0.2) = 0.1175 Pa (REFERENCE_RE20).

    Start: fluid at rest, p = 0; the inflow's U_max ramps up as sin^2(pi t / (2 ramp))
    over `ramp` seconds (a (t, speed) table), then holds: no impulsive start.

    Walls: dummy particles (Adami et al. 2012) with no-slip velocity and extrapolated
    pressure, along the channel and both open buffers, and the cylinder (wall group
    "cylinder"), a kernel support deep: `surface` = "rings" (default), concentric
    circles of particles dx apart at radii D/2 - dx/2, D/2 - 3 dx/2, ..., or "lattice",
    the fluid lattice's points inside the circle r < D/2 (a staircase); fluid: the
    lattice points with r >= D/2. dx must divide 0.01 m (D/dx = 10, 20, 30, 40...): the
    walls, the faces and the cylinder's centre then lie on cell corners. Morris laminar
    viscosity, Wendland kernel with h = 1.3 dx, predictor-corrector, and by default
    (chosen by the runs of docs/validation.md, "Flow past a cylinder"):

    - `density` = "summation" (the fluid's density summed over its neighbours and the
      walls, normalised by the kernel's sum over the lattice: SummationDensity(walls=True,
      lattice=True)) or "continuity" (evolved, with delta-SPH density diffusion `delta`,
      no hydrostatic correction);
    - `shifting` (particle shifting, Sun et al. 2017, at the mean speed, its sum over the
      walls too): it keeps the particles ordered where the wake's pressure is below the
      outlet's, so that no background pressure is needed;
    - `p_background` (Pa): the outlet's pressure and the fluid's initial one; default 0
      with shifting, 3.33 rho U_max^2 (0.3 Pa at re = 20) without.

    Why (the figures: docs/validation.md, "Flow past a cylinder"): without shifting and
    background pressure the wake's pressure goes negative and the tensile instability
    opens a cavity behind the cylinder (the channel loses mass); a background pressure
    prevents it but the symmetric pressure gradient turns it into a spurious drag that
    grows with the background pressure; shifting without background pressure gives the
    right wake, but with the continuity equation the channel loses mass steadily (the
    shift spreads the wake's particles, which the evolved density does not see); the
    summed density follows the particles. Its price: a noisier force (the means are
    steady). `c0` (default 30 U_max = 9 m/s at re = 20: 20 x the fastest speed, ~1.5
    U_max): a lower one lets the acoustic noise overfill the inlet buffer. `surface`:
    rings are the default since the staircase's maximum drag at Re 100 misses the
    benchmark's bar (rings meet it; their force is quieter); at Re 20 both meet it.

    At re = 100 (docs/validation.md, "Re 100"), at the default dx, the vortex shedding's
    Strouhal number and the maximum drag and lift meet the benchmark's bars.

    Probes (written by ``python -m taisph cylinder`` to OUT/probes.csv): the force of
    the fluid on the cylinder "cylinder" (pressure and viscous, N/m, every `every`
    steps) and the pressures "p_front" at (0.15, 0.2) and "p_back" at (0.25, 0.2),
    the cylinder's front and back points (Shepard interpolation of the fluid's
    pressure there). Measured against the references in docs/validation.md ("Flow
    past a cylinder"), by tools/studies/cylinder_study.py.
    """
    per_cm = round(0.01 / dx)
    if per_cm < 1 or not math.isclose(per_cm * dx, 0.01, rel_tol=1e-9):
        raise ParameterError(f"cylinder: dx = {dx:g} m must divide 0.01 m (dx = 0.01/k: D/dx = 10 k), so that the "
                             f"channel ({LENGTH:g} m x {HEIGHT:g} m) and the cylinder's centre fall on the lattice")
    u_max = 1.5 * re * NU / DIAMETER
    u_mean = 2.0 * u_max / 3.0
    c0 = 30.0 * u_max if c0 is None else c0  # 20 x the fastest speed, about 1.5 U_max
    if p_background is None:
        p_background = 0.0 if shifting else BACKGROUND * RHO * u_max**2
    fluid_material = Material("fluid", rho0=RHO, c0=c0, gamma=7.0)
    if density == "summation":  # before the walls' pass, which extrapolates the fluid's pressure
        terms = [SummationDensity(walls=True, lattice=True)]
    else:
        terms = [Continuity(walls=True), DensityDiffusion(delta=delta, hydrostatic=False)]
    terms += [PressureGradient(walls=True), LaminarViscosity(nu=NU, walls=True), AdamiWall()]
    if shifting:
        terms.append(ParticleShifting(shift_speed=u_mean))
    scene = Scene(name="cylinder", dim=2, dx=dx, smoothing_length=h_factor * dx,
                  domain=((0.0, 0.0), (LENGTH, HEIGHT)), materials=[fluid_material], terms=terms, kernel=kernel,
                  integrator=integrator, t_end=t_end, frames=frames,
                  description=(f"flow past a cylinder (Schaefer & Turek 1996), D = {DIAMETER:g} m, D/dx = "
                               f"{DIAMETER / dx:.3g}, Re = {re:g}: U_max = {u_max:.4g} m/s, mean {u_mean:.4g} m/s, "
                               f"c0 = {c0:g} m/s"))
    layers = support_layers(scene.support_radius, dx)
    points = lattice((0.0, 0.0), (LENGTH, HEIGHT), dx)
    r = np.linalg.norm(points - np.asarray(CENTRE), axis=1)
    solid = r < 0.5 * DIAMETER
    density = RHO * (1.0 + 7.0 * p_background / (RHO * c0**2)) ** (1.0 / 7.0)  # Tait, at p_background
    scene.add_fluid(points[~solid], density=density, mass=density * dx**2)
    body = points[solid & (r > 0.5 * DIAMETER - (layers + 1) * dx)]  # a support deep (and one spare)
    if surface == "rings":  # concentric rings dx apart, each dx from the next, instead of the staircase
        radii = 0.5 * DIAMETER - (np.arange(layers + 1) + 0.5) * dx
        body = np.concatenate([np.asarray(CENTRE) + rr * np.column_stack(
            [np.cos(a), np.sin(a)]) for rr in radii for a in [np.linspace(0, 2 * np.pi, max(3, round(
                2 * np.pi * rr / dx)), endpoint=False)]])
    # the inflow: U_max sin^2(pi t / (2 ramp)), held after the ramp
    if ramp > 0:
        times = np.linspace(0.0, ramp, 65)
        table = np.column_stack([times, u_max * np.sin(0.5 * np.pi * times / ramp) ** 2])
    else:
        table = u_max
    scene.add_open_boundary("inlet", at=(0.0, 0.0), to=(0.0, HEIGHT), velocity=table, profile="parabolic")
    scene.add_open_boundary("outlet", at=(LENGTH, 0.0), to=(LENGTH, HEIGHT), pressure=p_background)
    # channel walls below and above the fluid and both buffers, then the cylinder
    depth = max(z.layers for z in scene.open_boundaries) * dx
    below = lattice((-depth, -layers * dx), (LENGTH + depth, 0.0), dx)
    scene.add_walls(below)
    scene.add_walls(below + np.array([0.0, HEIGHT + layers * dx]))
    group = scene.add_walls(body)
    scene.wall_groups["cylinder"] = np.arange(group.start, group.stop)
    lo, hi = scene.domain
    scene.domain = (np.minimum(lo, below.min(axis=0) - dx),
                    np.maximum(hi, below.max(axis=0) + [0.0, HEIGHT + layers * dx] + dx))
    x0, y0 = CENTRE
    scene.probes += [force("cylinder", walls="cylinder", every=every),
                     pressure("p_front", at=(x0 - 0.5 * DIAMETER, y0), every=every),
                     pressure("p_back", at=(x0 + 0.5 * DIAMETER, y0), every=every)]
    return scene


def headline(sim, out) -> list:
    """The drag and lift coefficients C_D = 2 F_x / (rho U^2 D), C_L = 2 F_y / (rho U^2 D)
    (U the mean inflow speed) and the front-back pressure difference dp (Pa), against
    Schaefer & Turek's 2D-1 values at re = 20 (REFERENCE_RE20; steady after ~4 s): means
    over the last 2 s of OUT/probes.csv (the second half of a shorter run), or without
    it the values at the end (taisph.validation.cylinder: the same definitions)."""
    from taisph.run.results import Result, probe_table, sample_probes
    from taisph.validation.cylinder import WINDOW, coefficients

    re = sim.scene.case_parameters.get("re", 20.0)
    table = probe_table(out, ("cylinder_x", "cylinder_y", "p_front", "p_back"))
    if table is not None:
        c = coefficients(table, re)
        start = c["t"][-1] - min(WINDOW, 0.5 * (c["t"][-1] - c["t"][0]))
        last = c["t"] >= start
        note = f"mean over t in [{start:.3g}, {c['t'][-1]:.3g}] s of probes.csv"
    else:
        now = sample_probes(sim, [p for p in sim.scene.probes if p.name in ("cylinder", "p_front", "p_back")])
        c = coefficients({k: np.array([v]) for k, v in now.items()}, re)
        last, note = np.ones(1, bool), f"at t = {sim.time:.3g} s"
    reference = REFERENCE_RE20 if re == 20.0 else {}
    source = "Schaefer & Turek (1996), 2D-1" if reference else ""
    if reference and sim.time < 4.0:
        note += "; the reference is the steady flow's (t >= 4 s)"
    mean = {k: float(np.mean(c[k][last])) for k in ("C_D", "C_L", "dp")}
    return [Result("C_D", mean["C_D"], "1", reference.get("C_D"), source, note),
            Result("C_L", mean["C_L"], "1", reference.get("C_L"), source, note),
            Result("dp", mean["dp"], "Pa", reference.get("dp"), source, "p(0.15, 0.2) - p(0.25, 0.2), " + note)]
