"""Pressure-driven flow through a channel with an open inlet and outlet (non-periodic Poiseuille)."""

import math

import numpy as np

from taisph.geometry import lattice, support_layers
from taisph.scene import Material, Scene
from taisph.scene.parameters import (ParameterError, lattice_count, at_least, checked, end_time, flag, frame_count,
                                     known_integrator, known_kernel, one_of, positive, smoothing_factor)
from taisph.terms import (AdamiWall, Continuity, DensityDiffusion, Gravity, LaminarViscosity, ParticleShifting,
                          PressureGradient)


@checked(dx=positive, H=positive, L=positive, mu=positive, rho0=positive, p_in=positive, p_out=positive,
         c0=positive, h_factor=smoothing_factor, kernel=known_kernel, integrator=known_integrator,
         inlet=one_of("pressure", "velocity"), periodic=flag, delta=at_least(0), shifting=flag, t_end=end_time,
         frames=frame_count)
def channel(
    dx: float = 2.5e-5,
    H: float = 1e-3,
    L: float = 4e-3,
    mu: float = 2.5e-4,
    rho0: float = 1000.0,
    p_in: float = 0.2,
    p_out: float = 0.1,
    c0: float = 0.125,
    h_factor: float = 1.3,
    kernel: str = "wendland",
    integrator: str = "pc",
    inlet: str = "pressure",
    periodic: bool = False,
    delta: float = 0.1,
    shifting: bool = False,
    t_end: float = 3.0,
    frames: int = 30,
) -> Scene:
    """Water at rest between no-slip walls at y = 0 and y = H, open at x = 0 and x = L,
    driven from t = 0 by the pressure difference p_in - p_out (Pa) between an inlet and
    an outlet zone (:mod:`taisph.terms.open_boundary`; velocities extrapolated from the
    fluid). Steady state: the parabola u(y) = 4 u_max y (H - y) / H^2 with
    u_max = H^2 (p_in - p_out) / (8 mu L) = 0.0125 m/s by default (Re = rho u_max H / mu
    = 50), reached with the time constant tau = H^2 rho / (pi^2 mu) = 0.405 s.
    ``inlet="velocity"``: the inlet prescribes that parabola instead of p_in (the
    outlet keeps p_out). ``periodic=True``: the same channel closed on itself along x
    and driven by the body force (p_in - p_out) / (rho0 L) instead (the reference the
    open channel's cost is measured against, ``tools/bench_open.py``).

    The fluid starts at rest with the steady pressure, linear from p_in to p_out along
    x (its density by the Tait equation), so no pressure wave is launched. Walls:
    dummy particles (Adami et al. 2012) along the whole channel and its two buffers;
    Morris laminar viscosity; c0 = 10 u_max (Mach 0.1); Wendland kernel, h = 1.3 dx.
    dx = H/40 by default.
    """
    n_across, n_along = round(H / dx), round(L / dx)
    if n_across < 4 or not (math.isclose(n_across * dx, H, rel_tol=1e-9) and math.isclose(n_along * dx, L,
                                                                                           rel_tol=1e-9)):
        raise ParameterError(f"channel: dx = {dx:g} m must divide the height H = {H:g} m and the length L = {L:g} m "
                             "into whole numbers of particles, at least 4 across")
    lattice_count("channel", "the channel", dx, ("H", H), ("L", L))  # refused for memory before anything is built
    nu = mu / rho0
    u_max = H**2 * (p_in - p_out) / (8.0 * mu * L)
    water = Material("water", rho0=rho0, c0=c0, gamma=7.0)
    terms = [Continuity(walls=True), PressureGradient(walls=True), LaminarViscosity(nu=nu, walls=True), AdamiWall(),
             DensityDiffusion(delta=delta, hydrostatic=False)]
    if shifting:
        terms.append(ParticleShifting(shift_speed=u_max))
    scene = Scene(name="channel", dim=2, dx=dx, smoothing_length=h_factor * dx, domain=((0.0, 0.0), (L, H)),
                  materials=[water], terms=terms, kernel=kernel, integrator=integrator, t_end=t_end, frames=frames,
                  description=(f"pressure-driven channel, H = {H:g} m, L = {L:g} m, p_in - p_out = "
                               f"{p_in - p_out:g} Pa: u_max = {u_max:.4g} m/s, Re = {rho0 * u_max * H / mu:.3g}"))
    B = rho0 * c0**2 / 7.0
    fluid = lattice((0.0, 0.0), (L, H), dx)
    pressure = p_in + (p_out - p_in) * fluid[:, 0] / L
    density = rho0 * (1.0 + pressure / B) ** (1.0 / 7.0)
    scene.add_fluid(fluid, density=density, mass=density * dx**2)  # volume dx^2 each at its pressure
    if periodic:
        scene.periodic = (True, False)
        scene.terms.append(Gravity(gravity=((p_in - p_out) / (rho0 * L), 0.0)))
        layers = support_layers(scene.support_radius, dx)
        below = lattice((0.0, -layers * dx), (L, 0.0), dx)
        scene.add_walls(below)
        scene.add_walls(below + np.array([0.0, H + layers * dx]))
        scene.domain = (np.array([0.0, -(layers + 1) * dx]), np.array([L, H + (layers + 1) * dx]))
        return scene
    if inlet == "pressure":
        scene.add_open_boundary("inlet", at=(0.0, 0.0), to=(0.0, H), pressure=p_in)
    else:
        # ramped up over 0.2 s (a start at full speed sends a pressure wave of rho c0 u_max = 15 times
        # the channel's pressure drop, which drove particles into the walls by the inlet)
        ramp = np.array([[0.0, 0.0], [0.2, u_max]])
        scene.add_open_boundary("inlet", at=(0.0, 0.0), to=(0.0, H), velocity=ramp, profile="parabolic")
    scene.add_open_boundary("outlet", at=(L, 0.0), to=(L, H), pressure=p_out)
    # walls below and above the fluid and both buffers
    depth = max(z.layers for z in scene.open_boundaries) * dx
    layers = support_layers(scene.support_radius, dx)
    below = lattice((-depth, -layers * dx), (L + depth, 0.0), dx)
    scene.add_walls(below)
    scene.add_walls(below + np.array([0.0, H + layers * dx]))
    lo, hi = scene.domain
    scene.domain = (np.minimum(lo, below.min(axis=0) - dx), np.maximum(hi, below.max(axis=0) + [0.0, H + layers * dx]
                                                                       + dx))
    return scene


def headline(sim, out) -> list:
    """The flow rate Q (m^2/s per metre of depth) through the channel's middle cross-section
    at the end (a flow probe, taisph.probes), against the steady parabola's
    Q = 2/3 u_max H, u_max = H^2 (p_in - p_out) / (8 mu L); steady within 0.1 % after
    7 time constants H^2 rho / (pi^2 mu) (2.8 s by default)."""
    from taisph.probes import flow
    from taisph.run.results import Result, sample_probes

    p = sim.scene.case_parameters
    H, L = p["H"], p["L"]
    u_max = H**2 * (p["p_in"] - p["p_out"]) / (8.0 * p["mu"] * L)
    tau = H**2 * p["rho0"] / (math.pi**2 * p["mu"])
    q = sample_probes(sim, [flow("Q", at=(0.5 * L, 0.0), to=(0.5 * L, H))])["Q"]
    note = f"through x = L/2 at t = {sim.time:.3g} s" + (
        f"; the reference is the steady flow's (t >= {7 * tau:.2g} s)" if sim.time < 7 * tau else "")
    return [Result("Q", q, "m^2/s", 2.0 / 3.0 * u_max * H, "steady plane Poiseuille flow", note)]
