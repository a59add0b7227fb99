"""Start-up plane Poiseuille flow between no-slip walls, periodic along the channel (Morris, Fox & Zhu 1997)."""

import math

import numpy as np

from taisph.scene import Material, Scene
from taisph.geometry import lattice, support_layers, wall_layers
from taisph.terms import AdamiWall, Continuity, DensityDiffusion, Gravity, LaminarViscosity, PressureGradient
from taisph.scene.parameters import (ParameterError, checked, diffusion_delta, end_time, finite, frame_count,
                                     known_integrator, known_kernel, lattice_count, optional, positive,
                                     reference_density, smoothing_factor, speed_of_sound)


@checked(dx=positive, L=positive, nu=positive, F=finite, rho0=reference_density, c0=speed_of_sound,
         h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator, delta=optional(diffusion_delta),
         t_end=end_time, frames=frame_count)
def poiseuille(
    dx: float = 5e-5,
    L: float = 1e-3,
    nu: float = 1e-6,
    F: float = 2e-4,
    rho0: float = 1000.0,
    c0: float = 0.01,
    h_factor: float = 1.3,
    kernel: str = "spline",
    integrator: str = "pc",
    delta: float | None = None,
    t_end: float = 1.0,
    frames: int = 20,
) -> Scene:
    """Fluid at rest between walls at y = 0 and y = L (m), driven along x by a body
    force F (m/s^2) from t = 0; periodic in x. Morris et al. (1997): L = 1 mm,
    nu = 1e-6 m^2/s, rho0 = 1000, F = 2e-4 m/s^2, so the steady centre-line speed is
    F L^2/(8 nu) = 2.5e-5 m/s (Re = 0.025). dx = L/20 by default.

    Walls: dummy particles with extrapolated pressure and the no-slip velocity of
    Adami et al. (2012); Morris laminar viscosity; no artificial viscosity. c0 = 0.01
    m/s (Mach 2.5e-3; Morris et al.'s criterion c0^2 >= F L / 0.01 asks for 4.5e-3).
    Adaptive dt: the acoustic CFL and the viscous limit 0.125 h^2/nu of Morris et al.
    delta: density diffusion coefficient (no hydrostatic correction: the body force
    is balanced by the walls' shear, not by pressure), 0 or None for none.
    """
    return _channel("poiseuille", dx, L, nu, rho0, c0, h_factor, kernel, integrator, delta, t_end, frames,
                    force=F, wall_speed=0.0,
                    description=f"start-up Poiseuille flow, L = {L:g} m, nu = {nu:g} m^2/s, F = {F:g} m/s^2")


def _channel(name, dx, L, nu, rho0, c0, h_factor, kernel, integrator, delta, t_end, frames, force, wall_speed,
             description):
    n_across = round(L / dx)
    if n_across < 4 or not math.isclose(n_across * dx, L, rel_tol=1e-9):
        raise ParameterError(f"{name}: dx = {dx:g} m must divide the channel width L = {L:g} m into a whole "
                             f"number of layers, at least 4 (dx = L/4, L/5, ...)")
    water = Material("fluid", rho0=rho0, c0=c0, gamma=7.0)
    terms = [
        Continuity(walls=True),
        PressureGradient(walls=True),
        LaminarViscosity(nu=nu, walls=True),
        Gravity(gravity=(force, 0.0)),
        AdamiWall(),
    ]
    if delta:  # None or 0: no term
        terms.append(DensityDiffusion(delta=delta, hydrostatic=False))
    h = h_factor * dx
    scene = Scene(name=name, dim=2, dx=dx, smoothing_length=h, domain=((0.0, 0.0), (1.0, 1.0)),
                  materials=[water], terms=terms, kernel=kernel, integrator=integrator, t_end=t_end,
                  frames=frames, description=description, periodic=(True, False))
    support = scene.support_radius
    # periodic length: at least 3 kernel supports (the neighbour grid's minimum), whole particles
    n_along = math.ceil(3.0 * support / dx * (1 + 1e-9)) + 1
    length = n_along * dx
    lattice_count(name, "the channel", dx, ("L", L), ("its periodic length", length))
    layers = support_layers(support, dx)
    pad = (layers + 1) * dx
    scene.domain = (np.array([0.0, -pad]), np.array([length, L + pad]))
    scene.add_fluid(lattice((0.0, 0.0), (length, L), dx))
    walls = wall_layers((0.0, 0.0), (length, L), dx, layers, open_top=False, periodic=(True, False))
    scene.add_walls(walls[walls[:, 1] < 0])
    scene.add_walls(walls[walls[:, 1] > L], velocity=(wall_speed, 0.0))
    return scene


def headline(sim, out) -> list:
    """At the end, against Morris et al.'s (1997) series solution of the start-up flow
    (taisph.validation.references.analytic): the mean speed of the particle row nearest the
    centre line, and max |u - u_exact| over the fluid over the steady centre-line speed
    F L^2 / (8 nu) (taisph.validation.runs.poiseuille's error at each sample)."""
    from taisph.validation.references import analytic

    p = sim.scene.case_parameters
    L, nu, F = p["L"], p["nu"], p["F"]
    return channel_headline(sim, lambda y, t: analytic.poiseuille_startup(y, t, L, nu, F), F * L * L / (8 * nu), L)


def channel_headline(sim, exact, u_ref: float, L: float) -> list:
    """The headline of a start-up channel flow (poiseuille, couette): `exact(y, t)` the
    series solution, `u_ref` the speed the error is measured in, L the channel's width."""
    from taisph.run.results import Result

    x, u = sim.positions()[sim.fluid], sim.velocities()[sim.fluid][:, 0]
    row = np.abs(x[:, 1] - L / 2) <= np.abs(x[:, 1] - L / 2).min() + 0.25 * sim.scene.dx
    y, at = float(x[row, 1].mean()), f"at t = {sim.time:g} s"
    source = "Morris et al. (1997), series solution"
    return [Result("u_centre", float(u[row].mean()), "m/s", float(exact(np.array([y]), sim.time)[0]), source,
                   f"mean of the particle row at y = {y:.4g} m, {at}"),
            Result("max_error", float(np.abs(u - exact(x[:, 1], sim.time)).max() / u_ref) if u_ref else math.nan,
                   "1", None, "", f"max |u - u_exact| / {u_ref:.4g} m/s over the fluid, {at}")]
