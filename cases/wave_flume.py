"""Wave flume: a piston wave maker makes regular waves in still water (first-order
wave-maker theory, Dean & Dalrymple 1991; dispersion relation omega^2 = g k tanh kh)."""

import math

import numpy as np

from taisph.eos import Tait
from taisph.geometry import lattice, support_layers
from taisph.messages import InputError
from taisph.probes import body, elevation
from taisph.scene import Material, Scene
from taisph.scene import wave_makers
from taisph.scene.parameters import (ParameterError, checked, diffusion_delta, end_time, frame_count,
                                     gravity_magnitude, known_formulation, known_integrator, known_kernel,
                                     lattice_count, optional, at_least, positive, smoothing_factor, speed_of_sound,
                                     viscosity_alpha)
from taisph.scene.water import hydrostatic_density, sound_speed
from taisph.terms import (STANDARD_GRAVITY, AdamiWall, ArtificialViscosity, Continuity, DampingZone, DensityDiffusion,
                          Gravity, PressureGradient, Riemann)

GAUGES = (1.0, 2.0, 3.0)  # m from the piston's rest position: g1, g2, g3


@checked(dx=positive, length=positive, depth=positive, height=positive, period=positive, ramp=positive,
         absorber=at_least(0),
         alpha=viscosity_alpha, delta=optional(diffusion_delta), c0=optional(speed_of_sound),
         h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel, integrator=known_integrator,
         t_end=end_time, frames=frame_count, formulation=known_formulation)
def wave_flume(
    dx: float = 0.02,
    length: float = 10.0,
    depth: float = 0.5,
    height: float = 0.04,
    period: float = 1.5,
    ramp: float = 1.0,
    absorber: float = 0.0,
    alpha: float = 0.02,
    delta: float | None = 0.1,
    c0: float | None = None,
    h_factor: float = 2.0,
    g: float = STANDARD_GRAVITY,
    kernel: str = "wendland",
    integrator: str = "pc",
    t_end: float = 9.0,
    frames: int = 45,
    formulation: str = "symmetric",
):
    """A `length` x `depth` flume of still water with a piston at its left end making
    regular waves of `height` (m) and `period` (s), ramped up over `ramp` periods.

    Defaults: 10 m x 0.5 m, dx = 0.02 m (12 500 fluid particles), T = 1.5 s (kh = 1.111,
    wavelength 2.83 m), H = 0.04 m (steepness 0.014); the piston's stroke from
    first-order theory, S = H / [2 (cosh 2kh - 1) / (sinh 2kh + 2kh)] = H / 1.082
    (:func:`taisph.scene.wave_makers.piston`). Dummy walls without friction (a free-slip
    floor), the Wendland C2 kernel with h = 2 dx, Monaghan alpha = 0.02, density diffusion
    delta = 0.1, c0 = 10 sqrt(2 g depth). The kernel is what keeps the waves' height: with
    the cubic spline and h = 1.3 dx the wave lost 18 % of its height a metre at dx = 0.04 m,
    with Wendland and h = 2 dx 2 %, at the same wall time (fewer, longer steps;
    docs/bodies.md#piston-wave-maker). The far wall reflects: waves from it reach the
    gauges after (2 length - x) / c, 9 s at g3 with the defaults; `absorber` (m) puts a
    damping zone that long against the far wall (:class:`taisph.terms.DampingZone`, rate
    2 pi / period) to absorb them. `formulation`: "symmetric" (the seed's continuity and
    momentum equations, eqs. 7-8) or "riemann" (Zhang, Hu & Adams 2017,
    :class:`taisph.terms.Riemann`: its own low dissipation; give alpha = 0 and delta =
    None with it); alpha = 0 compiles no artificial viscosity.

    Probes (``python -m taisph wave_flume`` writes OUT/probes.csv): the piston as the body
    probe ``piston`` (``piston_x``: its centre, the rest position plus the stroke's
    displacement) and the wave gauges ``g1``, ``g2``, ``g3`` at 1, 2 and 3 m from the
    piston's rest position (free-surface height above the floor)."""
    try:
        motion = wave_makers.piston(height, period, depth, ramp=ramp, g=g)
    except InputError as err:  # (a breaking steepness: the message names height, period and depth)
        raise ParameterError(f"wave_flume: {err}") from None
    stroke = 2.0 * motion.stroke
    if stroke > 0.25 * length:
        raise ParameterError(f"wave_flume: the piston's stroke for height = {height:g} m and period = {period:g} s in "
                             f"depth = {depth:g} m is {stroke:.4g} m, more than a quarter of the flume's length = "
                             f"{length:g} m (long waves need a long stroke: give a shorter period or a lower height)")
    if length < GAUGES[-1] + 2 * dx:
        raise ParameterError(f"wave_flume: length = {length:g} m with dx = {dx:g} m leaves no room for the gauges "
                             f"(up to {GAUGES[-1]} m)")
    if depth < 4 * dx or height < dx / 4:
        raise ParameterError(f"wave_flume: dx = {dx:g} m does not resolve the water (depth = {depth:g} m needs "
                             f"depth / dx >= 4, height = {height:g} m needs height / dx >= 1/4)")
    lattice_count("wave_flume", "the flume", dx, ("length", length), ("depth", depth))
    c0 = sound_speed(g, depth) if c0 is None else c0
    water = Material("water", rho0=1000.0, c0=c0, gamma=7.0)
    # the continuity and momentum equations: the seed's symmetric form or the Riemann solver's
    equations = [Riemann(walls=True)] if formulation == "riemann" else [Continuity(walls=True),
                                                                         PressureGradient(walls=True)]
    terms = [*equations, *([ArtificialViscosity(alpha=alpha)] if alpha else []),
             Gravity(gravity=(0.0, -g)), AdamiWall()]
    if delta:
        terms.append(DensityDiffusion(delta=delta))
    if absorber:  # a sponge at the far end: waves die out instead of coming back
        if absorber > length - GAUGES[-1] - 2 * dx:
            raise ParameterError(f"wave_flume: absorber = {absorber:g} m reaches the gauges (the last at "
                                 f"{GAUGES[-1]} m) in a flume of length = {length:g} m")
        terms.append(DampingZone(damping_start=(length - absorber, 0.0), damping_direction=(absorber, 0.0),
                                 damping_rate=2 * math.pi / period))
    h = h_factor * dx
    top = depth + 3 * height + 0.1  # the walls' height: above the highest crest
    scene = Scene(name="wave_flume", dim=2, dx=dx, smoothing_length=h, domain=((0.0, 0.0), (1.0, 1.0)),
                  open_faces=("+y",), remove_escaped=True, materials=[water], eos=Tait(), terms=terms,
                  kernel=kernel, integrator=integrator, t_end=t_end, frames=frames,
                  description=f"piston wave maker, H = {height:g} m, T = {period:g} s in {depth:g} m of water "
                              f"(stroke {stroke:.4g} m), {length:g} m flume")
    layers = support_layers(scene.support_radius, dx)
    pad = layers * dx
    back = math.ceil((0.5 * stroke + dx) / dx) * dx  # the floor reaches under the piston's travel
    scene.domain = (np.array([-pad - back - dx, -pad - dx]), np.array([length + pad + dx, top + 0.5 * depth]))
    fluid = lattice((0.0, 0.0), (length, depth), dx)
    scene.add_fluid(fluid, density=hydrostatic_density(water, g, depth - fluid[:, 1]))
    scene.add_walls(lattice((-pad - back, -pad), (length + pad, 0.0), dx))  # floor
    scene.add_walls(lattice((length, 0.0), (length + pad, top), dx))  # far wall
    piston = lattice((-pad, 0.0), (0.0, top), dx)
    scene.add_body("piston", piston, motion="prescribed", trajectory=motion, axis=(1.0, 0.0), until=t_end)
    scene.probes += [body("piston", every=10),
                     *[elevation(f"g{k + 1}", at=(x,), every=10) for k, x in enumerate(GAUGES)]]
    return scene


def expected(depth=0.5, height=0.04, period=1.5, g=STANDARD_GRAVITY) -> dict:
    """First-order theory's numbers for the flume: wavenumber k, wavelength, kh, H/S, the
    piston's stroke, the phase speed c and the group speed c_g = c (1 + 2kh / sinh 2kh) / 2
    (Dean & Dalrymple 1991, ch. 4)."""
    k = wave_makers.wavenumber(period, depth, g)
    kh = k * depth
    ratio = wave_makers.piston_transfer(kh)
    celerity = 2 * math.pi / k / period
    return dict(k=k, wavelength=2 * math.pi / k, kh=kh, ratio=ratio, stroke=height / ratio, celerity=celerity,
                group=0.5 * celerity * (1 + 2 * kh / math.sinh(2 * kh)))


def headline(sim, out) -> list:
    """From the gauges' records in OUT/probes.csv: the wave height at each gauge (the mean
    crest-to-trough height over the whole periods between the full wave train's arrival and
    the far wall's reflection: taisph.validation.waves) against the target H (first-order
    wave-maker theory). A gauge whose window holds no whole period by the end reads nothing;
    without probes.csv, nothing."""
    from taisph.run.results import Result, probe_table
    from taisph.validation.waves import wave_height, window

    p = sim.scene.case_parameters
    names = [f"g{k + 1}" for k in range(len(GAUGES))]
    table = probe_table(out, names)
    if table is None:
        return []
    t = table["time"]
    results = []
    for name, x in zip(names, GAUGES):
        start, end = window(x, p["period"], p["depth"], p["ramp"], p["length"], float(t[-1]), bool(p["absorber"]),
                            p["g"])
        value = wave_height(t, table[name], start, end, p["period"]) if end > start else math.nan
        note = (f"at x = {x:g} m, mean over t in [{start:.3g}, {end:.3g}] s" if end > start else
                f"at x = {x:g} m: no whole period between the full wave train's arrival ({start:.3g} s) and the "
                f"record's end ({t[-1]:.3g} s) or the far wall's reflection")
        results.append(Result(f"height_{name}", value, "m", p["height"], "first-order wave-maker theory", note))
    return results
