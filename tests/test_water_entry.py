"""Water entry (issue 28, check 6, a demonstration; cases/water_entry.py): a cylinder of
half the water's density (D = 0.11 m) enters still water at sqrt(2 g 0.5 m) = 3.13 m/s
(Greenhow & Lin 1983), plunges and comes to float half submerged: no fluid particle lost
or inside the cylinder. At the end it should float at Archimedes' height for its own mass,
at rest; both are known misses at dx 0.005 (strict xfails with their measured values: the
splash's film weighs it down, the closed tank's slosh keeps it bobbing)."""

import functools

import numpy as np
import pytest

import taisph
from taisph.cases.water_entry import expected, water_entry
from taisph.geometry.shapes import ball


def inside(x, centre, angle, cells, dx, shift):
    """How many of the points `x` lie inside the cylinder's interior: in the dx-square cell
    of one of its particles whose four neighbours along the axes are its particles too, in
    its own frame (`cells`, `shift`: :func:`interior_cells`). Its surface row is left out: a lattice disc's edge is a
    staircase, and a fluid particle pressed into one of its notches sits between surface
    particles without having tunnelled into the body."""
    c, s = np.cos(angle), np.sin(angle)
    r = (x - centre) @ np.array([[c, -s], [s, c]])  # rotated by -angle: the body's frame
    keys = np.round(r / dx - shift).astype(np.int64)
    return sum(tuple(k) in cells for k in keys)


def interior_cells(offsets, dx):
    """(cells, shift) of a lattice body whose particles sit at `offsets` from its centre:
    the cells (offset / dx - shift, integers; shift 0 or 1/2, where the lattice sits) of
    the particles whose four axis neighbours are its particles too."""
    shift = offsets[0] / dx - np.round(offsets[0] / dx)
    keys = {tuple(k) for k in np.round(offsets / dx - shift).astype(np.int64)}
    assert len(keys) == len(offsets), "the body's particles are not on one lattice"
    return {(i, j) for i, j in keys if {(i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)} <= keys}, shift


def entry_run(dx, t_end, every=0.01, **params):
    """Sample every `every` s: the fluid's count, finiteness, the number of fluid particles
    inside the cylinder (:func:`inside`) and the nearest's distance (in dx); the cylinder's
    height and velocity, and the mass of the water resting on its upper part (:func:`film`)."""
    scene = water_entry(dx=dx, t_end=t_end, **params)
    sim = taisph.Simulation(scene)
    fluid = sim.fluid.copy()
    first = sim.bodies()["cylinder"]
    particles = np.flatnonzero(~fluid & _body_mask(sim, first.position, dx))
    assert len(particles) == expected(dx=dx)["particles"]
    cells, shift = interior_cells(sim.positions()[particles] - first.position, dx)
    intruders, heights, times, speeds, closest, films = [], [], [], [], [], []
    mass = sim.masses()[fluid][0]
    for k in range(int(round(t_end / every)) + 1):
        if k:
            sim.run(k * every, frames=0)
        x, v = sim.positions(), sim.velocities()
        assert np.isfinite(x).all() and np.isfinite(v).all() and np.isfinite(sim.density()).all(), sim.time
        assert (sim.fluid == fluid).all(), f"a fluid particle was removed at t = {sim.time:g} s"
        body = sim.bodies()["cylinder"]
        intruders.append(inside(x[fluid], body.position, body.orientation, cells, dx, shift))
        near = x[fluid][np.linalg.norm(x[fluid] - body.position, axis=1) < 0.055 + 2 * dx]
        closest.append(np.linalg.norm(near[:, None, :] - x[particles][None, :, :], axis=2).min() / dx
                       if len(near) else np.inf)
        heights.append(body.position[1])
        films.append(mass * film(x[fluid], body.position, dx))
        speeds.append(np.linalg.norm(body.velocity))
        times.append(sim.time)
    sim.close()
    print(f"dx = {dx:g} m: the nearest fluid particle came within {min(closest):.3g} dx of a cylinder "
          f"particle (at t = {times[int(np.argmin(closest))]:.3g} s), {closest[-1]:.3g} dx at the end; "
          f"fluid particles inside: {max(intruders)} at most; at the end the centre at {heights[-1]:.5g} m, "
          f"speed {speeds[-1]:.3g} m/s")
    return (np.array(times), np.array(heights), np.array(speeds), np.array(intruders), np.array(closest),
            np.array(films))


def film(x, centre, dx, radius=0.055):
    """How many of the fluid particles `x` rest on the cylinder's upper part: within 2 dx
    of its surface and more than 0.4 radius above its centre (above the waterline's
    meniscus: the cylinder floats with its centre at the water's level)."""
    r = x - centre
    return int(np.count_nonzero((np.linalg.norm(r, axis=1) < radius + 2 * dx) & (r[:, 1] > 0.4 * radius)))


def _body_mask(sim, centre, dx):
    """The particles within the cylinder's radius plus dx of its centre at t = 0 (only its
    own: the water and walls start farther away)."""
    return np.linalg.norm(sim.positions() - centre, axis=1) < 0.055 + dx


def test_expected_numbers():
    """The lattice disc (dx = 0.005 m: 384 particles, its area 1.0 % above pi D^2 / 4)
    floats with its centre at the water's level, raised by half its area over the tank's
    width."""
    ex = expected()
    assert ex["particles"] == 384 and ex["area"] == pytest.approx(np.pi * 0.055**2, rel=0.015)
    assert ex["centre"] == pytest.approx(ex["level"], abs=1e-12)
    assert ex["level"] == pytest.approx(0.5 + ex["area"] / 2, abs=1e-12)


def test_inside_counts_the_interior_not_the_surface_row():
    """The cylinder's centre is inside; a point 0.0516 m from it at 45 degrees, between the
    staircase's surface particles (a fluid particle sat there at rest in a run at dx =
    0.005 m), is not; one a row deeper is."""
    dx = 0.005
    disc = ball((0.0, 0.0), 0.055, dx)
    cells, shift = interior_cells(disc - disc.mean(axis=0), dx)
    diagonal = np.array([1.0, 1.0]) / np.sqrt(2)
    assert inside(np.zeros((1, 2)), np.zeros(2), 0.0, cells, dx, shift) == 1
    assert inside(0.0516 * diagonal[None], np.zeros(2), 0.0, cells, dx, shift) == 0
    assert inside((0.0516 - 1.5 * dx) * diagonal[None], np.zeros(2), 0.0, cells, dx, shift) == 1
    assert inside(0.0516 * diagonal[None] + 0.1, np.full(2, 0.1), 0.3, cells, dx, shift) == 0


def test_a_cylinder_enters_the_water_quick():
    """Coarse and small (dx = 0.01 m, a 0.5 m x 0.25 m tank, 0.6 s): the cylinder enters at
    3.13 m/s, sinks, stops and rises; no fluid particle lost, none inside the cylinder
    (in the cell of one of its interior particles: :func:`inside`), the state finite."""
    dx = 0.01
    t, y, _, intruders, _, _ = entry_run(dx, 0.6, tank_width=0.5, depth=0.25)
    assert intruders.max() == 0, (intruders.max(), t[np.argmax(intruders)])
    deepest = int(np.argmin(y))
    assert y[deepest] < 0.25 - 0.055, "the cylinder did not sink below the surface"
    assert 0 < deepest < len(y) - 1 and y[-1] > y[deepest] + dx, "it did not stop and rise"


@functools.lru_cache(maxsize=1)
def fine_run():
    """Issue 28, check 6, dx = 0.005 m (D/dx = 22), 1 m x 0.5 m tank, to 4 s (one run for
    the three slow tests: 24 min of CPU on one thread at load 4-7, 2026-12-07)."""
    return entry_run(0.005, 4.0)


def last_second(dx=0.005):
    """The fine run's last second (3-4 s): the centre's mean height less Archimedes' for
    the cylinder's own mass, in dx; its largest speed (m/s); and, reported beside (not
    asserted), the film of water on its top (:func:`film`, kg/m) and the height less
    Archimedes' for its mass plus the film's, the tank (1 m wide) having given that water."""
    t, y, speed, _, _, films = fine_run()
    last = t >= t[-1] - 1.0
    ex = expected(dx=dx)
    load = films[last].mean()
    loaded = expected(dx=dx, density=(ex["mass"] + load) / ex["area"])["centre"] - load / 1000.0 / 1.0
    found = {"height": (y[last].mean() - ex["centre"]) / dx, "speed": speed[last].max(), "film": load,
             "film share": load / ex["mass"], "height with the film": (y[last].mean() - loaded) / dx}
    print({key: round(float(value), 4) for key, value in found.items()})
    return found


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="measured 2026-12-07 (dx 0.005, 3-4 s): 0.614 dx below Archimedes' height "
                   "for its own mass; the splash's film on its top, 0.432 kg/m (9.0 % of its mass) held by the "
                   "wall friction, weighs it down (0.169 dx above the height for its mass plus the film's)")
def test_a_cylinder_dropped_into_water_floats_at_archimedes_height():
    """Issue 28, check 6, dx = 0.005 m: over the last second (3-4 s) the cylinder's mean
    centre height within 0.5 dx of Archimedes' for its own mass (lattice area x 500
    kg/m^3). A known miss (strict xfail): the film the splash leaves on its top rides with
    it (:func:`last_second` prints its mass and the height it would give)."""
    assert abs(last_second()["height"]) < 0.5


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="measured 2026-12-07 (dx 0.005): up to 0.0667 m/s over 3-4 s (0.0645 m/s at "
                   "4 s): it bobs on the closed 1 m tank's sloshing (1-2.5 dx, period about 0.8 s), which the "
                   "case's reflecting walls keep up")
def test_a_cylinder_dropped_into_water_comes_to_rest():
    """Issue 28, check 6, dx = 0.005 m: over the last second (3-4 s) the cylinder's speed
    stays below 0.05 m/s (1.6 % of its entry speed, 3.13 m/s). A known miss (strict
    xfail): the tank's slosh, not the float, keeps it moving."""
    assert last_second()["speed"] < 0.05


@pytest.mark.slow
def test_no_fluid_particle_enters_the_cylinder():
    """Issue 28, check 6, dx = 0.005 m: no fluid particle ever in the cell of one of the
    cylinder's interior particles (:func:`inside`), none nearer a cylinder particle than
    dx/4 (measured 0.497 dx at 2.87 s: the fluid's contact with bodies holds water at dx/2;
    before it, 2 particles sat in the interior cells at 2.37 s and one came within 0.0094 dx
    of a cylinder particle, water films left on its dry top settling onto its particles)."""
    t, _, _, intruders, closest, _ = fine_run()
    assert intruders.max() == 0, (intruders.max(), t[np.argmax(intruders)])
    assert closest.min() > 0.25, (closest.min(), t[np.argmin(closest)])
