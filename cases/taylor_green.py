"""Taylor-Green vortex in a periodic box: viscous decay of four vortices (Taylor & Green 1937; PySPH's set-up)."""

import math

from taisph.validation.references import analytic
from taisph.scene import Material, Scene
from taisph.geometry import lattice
from taisph.terms import (ArtificialViscosity, Continuity, DensityDiffusion, LaminarViscosity, ParticleShifting,
                          PressureGradient, XSPH)
from taisph.eos import tait
from taisph.scene.parameters import (ParameterError, checked, diffusion_delta, end_time, flag, frame_count,
                                     known_integrator, known_kernel, lattice_count, optional, positive,
                                     reference_density, smoothing_factor, speed_of_sound, viscosity_alpha,
                                     xsph_epsilon)


@checked(dx=positive, Re=positive, U=positive, L=positive, rho0=reference_density, c0=optional(speed_of_sound),
         h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator, alpha=optional(viscosity_alpha),
         delta=optional(diffusion_delta), xsph=optional(xsph_epsilon), shifting=flag, t_end=end_time,
         frames=frame_count)
def taylor_green(
    dx: float = 0.02,
    Re: float = 100.0,
    U: float = 1.0,
    L: float = 1.0,
    rho0: float = 1.0,
    c0: float | None = None,
    h_factor: float = 1.3,
    kernel: str = "spline",
    integrator: str = "pc",
    alpha: float | None = None,
    delta: float | None = 0.1,
    xsph: float | None = None,
    shifting: bool = True,
    t_end: float = 2.0,
    frames: int = 20,
):
    """u = -U e^{-8 pi^2 t/Re} cos(2 pi x/L) sin(2 pi y/L), v = ... sin cos, in the
    periodic box [0, L]^2 (four vortices), nu = U L / Re. PySPH's set-up: L = U = 1,
    Re = 100, rho0 = 1, c0 = 10 U; dx = L/50 by default (50 x 50 particles).

    Particles start on a square lattice with the exact velocity, and the density
    that gives the exact pressure through the Tait equation. Morris laminar
    viscosity; no artificial viscosity unless `alpha` is set. shifting: particle
    shifting (Sun et al. 2017) with U as reference speed - on by default: without it
    the lattice tears at the vortices' stagnation points by t ~ 0.2 and the solution
    is lost. delta: density diffusion coefficient (0.1 by default, 0 or None: off);
    xsph: XSPH epsilon (0 or None: off). Adaptive dt: the acoustic CFL and the viscous limit 0.125 h^2/nu.
    """
    n = round(L / dx)
    if n < 8 or not math.isclose(n * dx, L, rel_tol=1e-9):
        raise ParameterError(f"taylor_green: dx = {dx:g} m must divide L = {L:g} m into a whole number of "
                             f"particles, at least 8 (dx = L/8, L/9, ...)")
    lattice_count("taylor_green", "the periodic box", dx, ("L", L), ("L", L))
    c0 = 10.0 * U if c0 is None else c0
    # the initial pressure p = -rho0 U^2/4 (cos 4 pi x/L + cos 4 pi y/L) reaches -rho0 U^2/2, and the
    # Tait density of a pressure below -rho0 c0^2/7 does not exist
    if not c0 > math.sqrt(3.5) * U:
        raise ParameterError(f"taylor_green: c0 = {c0:g} m/s must exceed sqrt(7/2) U = {math.sqrt(3.5) * U:g} m/s, "
                             f"or the initial pressure (down to -rho0 U^2/2) has no Tait density; use c0 >= 10 U")
    nu = U * L / Re
    fluid = Material("fluid", rho0=rho0, c0=c0, gamma=7.0)
    terms = [Continuity(), PressureGradient(), LaminarViscosity(nu=nu)]
    if alpha is not None:
        terms.append(ArtificialViscosity(alpha=alpha))
    if delta:  # None or 0: no term
        terms.append(DensityDiffusion(delta=delta, hydrostatic=False))
    if xsph:  # None or 0: no term
        terms.append(XSPH(xsph_eps=xsph))
    if shifting:
        terms.append(ParticleShifting(shift_speed=U))
    h = h_factor * dx
    scene = Scene(name="taylor_green", dim=2, dx=dx, smoothing_length=h, domain=((0.0, 0.0), (L, L)),
                  periodic=(True, True), materials=[fluid], terms=terms, kernel=kernel, integrator=integrator,
                  t_end=t_end, frames=frames,
                  description=f"Taylor-Green vortex, Re = {Re:g}, {n} x {n} particles in a periodic box")
    if 3 * scene.support_radius > L:  # the neighbour grid needs 3 cells along a period
        raise ParameterError(f"taylor_green: the periodic box (L = {L:g} m) must span 3 kernel supports, 3 x "
                             f"{scene.support_radius:g} m (h_factor = {h_factor:g}, dx = {dx:g} m, {kernel} kernel): "
                             f"use a smaller dx or h_factor")
    pts = lattice((0.0, 0.0), (L, L), dx)
    u, v, p = analytic.taylor_green(pts[:, 0], pts[:, 1], 0.0, U=U, L=L, nu=nu, rho=rho0)
    scene.add_fluid(pts, velocity=list(zip(u, v)), density=tait.density(p, rho0, c0, 7.0))
    return scene


def headline(sim, out) -> list:
    """At the end, against the exact decaying vortex (taisph.validation.references.analytic):
    the largest speed, against U exp(-8 pi^2 nu t / L^2), and PySPH's L1 speed error,
    mean ||v| - |v_exact|| / mean |v_exact| (as taisph.validation.runs.taylor_green)."""
    import numpy as np

    from taisph.run.results import Result

    p = sim.scene.case_parameters
    U, L, nu = p["U"], p["L"], p["U"] * p["L"] / p["Re"]
    x, v = sim.positions(), sim.velocities()
    ue, ve, _ = analytic.taylor_green(x[:, 0], x[:, 1], sim.time, U=U, L=L, nu=nu, rho=p["rho0"])
    speed, exact = np.hypot(v[:, 0], v[:, 1]), np.hypot(ue, ve)
    at, source = f"at t = {sim.time:.3g} s", "Taylor & Green (1937), exact decay"
    return [Result("max_speed", float(speed.max()), "m/s", U * math.exp(-8 * math.pi**2 * nu * sim.time / L**2),
                   source, at),
            Result("L1_speed_error", float(np.mean(np.abs(speed - exact)) / np.mean(exact)), "1", None, "",
                   f"mean ||v| - |v_exact|| / mean |v_exact|, {at}")]
