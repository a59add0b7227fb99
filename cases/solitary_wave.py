"""Solitary wave: a piston moved on Goring's (1978) trajectory makes one solitary wave of
height H in still water of depth h, which runs down a flume at c = sqrt(g (h + H))
(Boussinesq 1872) past two wave gauges."""

import math

import numpy as np

from taisph.eos import Tait
from taisph.geometry import lattice, support_layers
from taisph.messages import InputError
from taisph.probes import body, elevation
from taisph.scene import Material, Scene
from taisph.scene import wave_makers
from taisph.scene.parameters import (ParameterError, checked, diffusion_delta, end_time, frame_count,
                                     gravity_magnitude, known_integrator, known_kernel, lattice_count, optional,
                                     positive, smoothing_factor, speed_of_sound, viscosity_alpha)
from taisph.scene.water import hydrostatic_density, sound_speed
from taisph.terms import (STANDARD_GRAVITY, AdamiWall, ArtificialViscosity, Continuity, DensityDiffusion, Gravity,
                          PressureGradient)

GAUGES = (1.5, 2.5)  # m from the piston's rest position: g1, g2


@checked(dx=positive, length=positive, depth=positive, height=positive,
         alpha=viscosity_alpha, delta=optional(diffusion_delta), c0=optional(speed_of_sound),
         h_factor=smoothing_factor, g=gravity_magnitude, kernel=known_kernel, integrator=known_integrator,
         t_end=end_time, frames=frame_count)
def solitary_wave(
    dx: float = 0.01,
    length: float = 4.0,
    depth: float = 0.14,
    height: float = 0.05,
    alpha: float = 0.01,
    delta: float | None = 0.1,
    c0: float | None = None,
    h_factor: float = 1.3,
    g: float = STANDARD_GRAVITY,
    kernel: str = "spline",
    integrator: str = "pc",
    t_end: float = 3.5,
    frames: int = 35,
):
    """A `length` flume of still water `depth` deep with a piston at its left end that
    makes one solitary wave of `height` (m) (:func:`taisph.scene.wave_makers.solitary_piston`:
    Goring 1978; Goring & Raichlen 1980).

    Defaults: 4 m x 0.14 m, dx = 0.01 m (h/14: 5600 fluid particles), H = 0.05 m
    (H/h = 0.357): the piston travels the stroke S = sqrt(16 H h / 3) = 0.193 m in 2.42 s,
    fastest (c H / (h + H) = 0.36 m/s) at t_c = 1.21 s, when the crest leaves it; the
    crest then runs at c = sqrt(g (h + H)) = 1.365 m/s (Boussinesq 1872; Rayleigh 1876),
    past g1 at about 2.2 s and g2 at about 3.0 s, and reaches the far wall at about 4.0 s,
    so that nothing reflected reaches the gauges before t_end = 3.5 s. The floor reaches
    under the piston's travel. Dummy walls without friction (a free-slip floor), Monaghan
    alpha = 0.01 (little numerical damping of the wave), density diffusion delta = 0.1,
    c0 = 10 sqrt(2 g depth).

    Probes (``python -m taisph solitary_wave`` writes OUT/probes.csv): the piston as the
    body probe ``piston`` (``piston_x``: its centre, the rest position plus Goring's
    displacement) and the wave gauges ``g1`` and ``g2`` at 1.5 m and 2.5 m from the
    piston's rest position (free-surface height above the floor: the crest height is
    max(g) - depth, the celerity (2.5 - 1.5) m over the difference of the crests' times)."""
    try:
        motion = wave_makers.solitary_piston(height, depth, g=g)
    except InputError as err:  # (too high: the message names height and depth)
        raise ParameterError(f"solitary_wave: {err}") from None
    if length < GAUGES[-1] + 4 * dx:
        raise ParameterError(f"solitary_wave: length = {length:g} m with dx = {dx:g} m leaves no room for the "
                             f"gauges (up to {GAUGES[-1]} m)")
    if depth < 4 * dx or height < dx / 4:
        raise ParameterError(f"solitary_wave: dx = {dx:g} m does not resolve the water (depth = {depth:g} m needs "
                             f"depth / dx >= 4, height = {height:g} m needs height / dx >= 1/4)")
    if motion.stroke > 0.25 * length:
        raise ParameterError(f"solitary_wave: the piston's stroke for height = {height:g} m in depth = {depth:g} m "
                             f"is {motion.stroke:.4g} m, more than a quarter of the flume's length = {length:g} m")
    lattice_count("solitary_wave", "the flume", dx, ("length", length), ("depth", depth))
    c0 = sound_speed(g, depth) if c0 is None else c0
    water = Material("water", rho0=1000.0, c0=c0, gamma=7.0)
    terms = [Continuity(walls=True), PressureGradient(walls=True), ArtificialViscosity(alpha=alpha),
             Gravity(gravity=(0.0, -g)), AdamiWall()]
    if delta:
        terms.append(DensityDiffusion(delta=delta))
    h = h_factor * dx
    top = depth + 2 * height + 0.1  # the walls' height: above the crest and its run-up on the far wall
    celerity = math.sqrt(g * (depth + height))
    scene = Scene(name="solitary_wave", dim=2, dx=dx, smoothing_length=h, domain=((0.0, 0.0), (1.0, 1.0)),
                  open_faces=("+y",), remove_escaped=True, materials=[water], eos=Tait(), terms=terms,
                  kernel=kernel, integrator=integrator, t_end=t_end, frames=frames,
                  description=f"solitary wave, H = {height:g} m in {depth:g} m of water (Goring's piston, stroke "
                              f"{motion.stroke:.4g} m; celerity sqrt(g (h + H)) = {celerity:.4g} m/s), "
                              f"{length:g} m flume")
    layers = support_layers(scene.support_radius, dx)
    pad = layers * dx
    scene.domain = (np.array([-2 * pad - dx, -pad - dx]), np.array([length + pad + dx, top + 0.5 * depth]))
    fluid = lattice((0.0, 0.0), (length, depth), dx)
    scene.add_fluid(fluid, density=hydrostatic_density(water, g, depth - fluid[:, 1]))
    scene.add_walls(lattice((-2 * pad, -pad), (length + pad, 0.0), dx))  # floor, under the piston's travel too
    scene.add_walls(lattice((length, 0.0), (length + pad, top), dx))  # far wall
    piston = lattice((-pad, 0.0), (0.0, top), dx)
    until = min(t_end, motion.duration)
    scene.add_body("piston", piston, motion="prescribed", trajectory=motion, axis=(1.0, 0.0), until=until)
    scene.probes += [body("piston", every=10),
                     *[elevation(f"g{k + 1}", at=(x,), every=5) for k, x in enumerate(GAUGES)]]
    return scene


def expected(depth=0.14, height=0.05, g=STANDARD_GRAVITY) -> dict:
    """Boussinesq's solitary wave: celerity sqrt(g (h + H)), Goring's stroke and duration,
    when the crest leaves the piston (t_c) and passes each gauge (x - S/2) / c later."""
    motion = wave_makers.solitary_piston(height, depth, g=g)
    c = math.sqrt(g * (depth + height))
    t_c = motion.duration / 2
    return dict(celerity=c, stroke=motion.stroke, duration=motion.duration, t_c=t_c,
                crest_times=tuple(t_c + (x - motion.stroke / 2) / c for x in GAUGES))


def headline(sim, out) -> list:
    """From the gauges' records in OUT/probes.csv: the crest height at each gauge (its
    highest sample's parabola's top, less the depth) against H, and the celerity between
    them (their distance over the crests' times' difference) against sqrt(g (h + H))
    (tests/test_solitary_wave.py measures them so). A crest counts once the record has
    passed it; without probes.csv, nothing."""
    from taisph.run.results import Result, probe_table

    p = sim.scene.case_parameters
    names = [f"g{k + 1}" for k in range(len(GAUGES))]
    table = probe_table(out, names)
    if table is None:
        return []
    crests = [_crest(table["time"], table[name] - p["depth"], p["height"]) for name in names]
    source = "Boussinesq (1872), Goring (1978)"
    results = [Result(f"crest_{name}", top, "m", p["height"], source,
                      f"at x = {x:g} m, t = {t:.3g} s" if math.isfinite(t) else "the crest has not passed by the end")
               for name, x, (t, top) in zip(names, GAUGES, crests)]
    (t1, _), (t2, _) = crests[0], crests[-1]
    celerity = (GAUGES[-1] - GAUGES[0]) / (t2 - t1) if math.isfinite(t1 + t2) and t2 > t1 else math.nan
    results.append(Result("celerity", celerity, "m/s", math.sqrt(p["g"] * (p["depth"] + p["height"])), source,
                          f"between {names[0]} and {names[-1]}"))
    return results


def _crest(t, eta, height) -> tuple:
    """(time, height) of the crest of `eta`: its highest sample and its neighbours' parabola's
    top; (nan, nan) unless a wave of at least height / 2 has passed (the record goes on
    after its highest sample)."""
    k = int(np.nanargmax(eta))
    if not 0 < k < len(eta) - 1 or not eta[k] >= 0.5 * height:
        return math.nan, math.nan
    y0, y1, y2 = eta[k - 1:k + 2]
    curve = y0 - 2 * y1 + y2
    s = 0.5 * (y0 - y2) / curve if curve else 0.0  # the vertex, in samples from k (|s| <= 1/2)
    return float(t[k] + s * (t[k + 1] - t[k])), float(y1 - 0.25 * (y0 - y2) * s)
