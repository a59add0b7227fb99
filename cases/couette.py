"""Start-up plane Couette flow: the upper wall starts moving, periodic along the channel (Morris, Fox & Zhu 1997)."""

from taisph.scene.parameters import (checked, diffusion_delta, end_time, finite, frame_count, known_integrator,
                                     known_kernel, optional, positive, reference_density, smoothing_factor,
                                     speed_of_sound)

from .poiseuille import _channel


@checked(dx=positive, L=positive, nu=positive, V0=finite, rho0=reference_density, c0=speed_of_sound,
         h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator, delta=optional(diffusion_delta),
         t_end=end_time, frames=frame_count)
def couette(
    dx: float = 5e-5,
    L: float = 1e-3,
    nu: float = 1e-6,
    V0: float = 1.25e-5,
    rho0: float = 1000.0,
    c0: float = 0.01,
    h_factor: float = 1.3,
    kernel: str = "spline",
    integrator: str = "pc",
    delta: float | None = None,
    t_end: float = 1.0,
    frames: int = 20,
):
    """Fluid at rest between walls at y = 0 and y = L (m); at t = 0 the upper wall
    starts moving along x at V0 (m/s); periodic in x. Morris et al. (1997): L = 1 mm,
    nu = 1e-6 m^2/s, V0 = 1.25e-5 m/s (Re = 0.0125). Same walls, viscosity, sound speed
    and time step as ``poiseuille``; no body force.
    """
    return _channel("couette", dx, L, nu, rho0, c0, h_factor, kernel, integrator, delta, t_end, frames,
                    force=0.0, wall_speed=V0,
                    description=f"start-up Couette flow, L = {L:g} m, nu = {nu:g} m^2/s, V0 = {V0:g} m/s")


def headline(sim, out) -> list:
    """At the end, against Morris et al.'s (1997) series solution: the mean speed of the
    particle row nearest the centre line, and max |u - u_exact| / V0 over the fluid
    (poiseuille's :func:`channel_headline`)."""
    from taisph.validation.references import analytic

    from .poiseuille import channel_headline

    p = sim.scene.case_parameters
    L, nu, V0 = p["L"], p["nu"], p["V0"]
    return channel_headline(sim, lambda y, t: analytic.couette_startup(y, t, L, nu, V0), abs(V0), L)
