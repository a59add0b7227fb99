"""Archimedes from away from the answer (issue 51, item 1): a floating box released below,
above and rolled from its equilibrium must settle at Archimedes' draft and upright.

The older Archimedes tests (tests/test_bodies.py) start the box at its equilibrium draft,
so that a buoyancy error of ~9 % passes them. Here the box, 1.0 m x 0.5 m of 500 kg/m^3
(Archimedes' draft d_A = 0.5 x 0.5 m = 0.25 m; wide enough to be stable upright: its
metacentric height b^2 / (12 d_A) - (H - d_A) / 2 = +0.21 m, where the case's square
0.5 m box is unstable, docs/bodies.md), floats in the middle of cases/floating_box's tank,
2.5 m wide, with water 0.8 m deep, and is let go from rest

- "deeper": its bottom 0.35 m below the still surface (1.4 d_A),
- "higher": 0.15 m below it (0.6 d_A: above its equilibrium, still touching water),
- "rolled": at d_A, rolled 15 deg about its centre,

and runs until its bobbing has died out (the case's own damping: Monaghan alpha = 0.1,
the wall friction and the waves it radiates; heave period about 1 s, settled within a
few seconds). What is read, time means over the last part of the run (sampled every 0.05 s):

- the draft: the water level at the case's gauge (x = 0.15 tank width, the highest fluid
  particle there plus dx/2) less the bottom of the box (its centre minus H/2), against d_A;
- the centre height against the one water conservation predicts before the run: the
  water's volume V = N_fluid dx^2 (its lattice cells; the box's volume has none) and the
  box at rest upright at d_A give the level L = (V + b d_A) / W and the centre
  L - d_A + H/2. The level moves with the box (the deeper release starts with the level
  0.04 m too high); a buoyancy error e moves the centre by e d_A (1 - b/W) = 0.6 e d_A;
- the level at the gauge against L (water conserved, and the gauge reads it);
- the roll, absolute, against upright.

Expected discretisation error: the box's effective surface is the fluid's first particle
layer, dx from its outer row where the water's and the box's lattices line up. A heave
keeps them aligned (measured within 0.6 % of d_A at dx 0.05); after a roll the layer under
the box settles 0.95-1.2 dx from its bottom row (traced at dx 0.05: not 1 dx as in a
lattice), and the box floats ~0.15 dx high: 3 % of d_A at dx = 0.05 m (d_A = 5 dx),
0.6-1.2 % at 0.025 m. The bars: 3 % (heave: about three times the largest measured,
0.9 % over 4-10 s of a 10 s run) and 5 % (roll) at dx 0.05; 2.5 % at dx 0.025 (twice the
largest error measured there); the roll within 0.75 deg (three times the 0.23 deg
measured at dx 0.05). A 9 % buoyancy error fails them: the quick runs with a box of 545
kg/m^3 (9 % heavier than d_A is computed for, the same as a buoyancy 9 % too weak) give
drafts 8.5 %, 8.4 % and 6.5 % over d_A (test_the_bars_catch_a_9_percent_buoyancy_error;
with 455 kg/m^3 the deeper release's is -9.9 %).

Commands: ``python -m pytest tests/test_archimedes_release.py -n 0 -s`` (the quick
tests, 36 s on this 2-core VM, 2026-12-07); ``-m slow`` for the others (5 min)."""

import math

import numpy as np
import pytest

import taisph
from taisph.cases.dam_break import _dam_break
from taisph.cases.floating_box import RHO_WATER, _drop
from taisph.geometry import lattice
from taisph.terms import STANDARD_GRAVITY

TANK, DEPTH, WIDTH, HEIGHT, DENSITY = 2.5, 0.8, 1.0, 0.5, 500.0
DRAFT = DENSITY / RHO_WATER * HEIGHT  # Archimedes: 0.25 m
GAUGE = 0.15 * TANK  # the case's gauge, away from the box
RELEASES = {"deeper": (1.4 * DRAFT, 0.0), "higher": (0.6 * DRAFT, 0.0), "rolled": (DRAFT, math.radians(15.0))}


def released_box(dx, release, t_end, density=DENSITY):
    """cases/floating_box with the box let go at the draft and roll of RELEASES[release]:
    upright through the case's box_bottom; rolled, the case's tank and water (its
    _dam_break call) with the fluid in the turned box's volume (and within dx/4 of it)
    removed and the turned lattice added as the case adds its box."""
    draft, roll = RELEASES[release]
    if roll == 0.0:
        return taisph.cases.floating_box(dx=dx, tank_width=TANK, depth=DEPTH, box_width=WIDTH, box_height=HEIGHT,
                                         box_density=density, box_bottom=DEPTH - draft, t_end=t_end, frames=0)
    scene = _dam_break(2, dx, TANK, DEPTH, None, TANK, DEPTH + HEIGHT + 0.5, 0.1, None, 1.3, STANDARD_GRAVITY,
                       "spline", "pc", t_end, 0, "floating_box")
    centre = np.array([TANK / 2, DEPTH - draft + HEIGHT / 2])
    turn = np.array([[math.cos(roll), -math.sin(roll)], [math.sin(roll), math.cos(roll)]])
    local = (scene.position - centre) @ turn  # in the box's frame
    inside = (np.abs(local[:, 0]) < WIDTH / 2 + dx / 4) & (np.abs(local[:, 1]) < HEIGHT / 2 + dx / 4)
    _drop(scene, inside & (scene.kind == 0))
    scene.add_body("box", centre + lattice((-WIDTH / 2, -HEIGHT / 2), (WIDTH / 2, HEIGHT / 2), dx) @ turn.T,
                   density=density)
    return scene


def window_samples(scene, t_end, window, every):
    """Run `scene` to `t_end`: the box's state and the fluid's positions every `every`
    seconds over the last `window` (the samples both settling tests average), and the
    number of fluid particles left at the end."""
    sim = taisph.Simulation(scene)
    sim.run(t_end - window, frames=0)
    samples = []
    for k in range(1, round(window / every) + 1):
        sim.run(t_end - window + every * k, frames=0)
        samples.append((sim.bodies()["box"], sim.positions()[sim.fluid]))
    return samples, int(np.sum(sim.fluid))


def settle(dx, release, t_end, window, density=DENSITY) -> dict:
    """Run the release to `t_end`, sampling every 0.05 s over the last `window` seconds:
    the relative errors of the draft (gauge level less bottom) and of the centre height
    (against the mass balance's, in units of d_A), the level's error in dx, the mean and
    largest absolute roll in degrees, the centre's standard deviation in dx, and the
    fluid particles lost."""
    scene = released_box(dx, release, t_end, density)
    roll = RELEASES[release][1]
    fluid = int(np.sum(scene.kind == 0))
    level = (fluid * dx * dx + WIDTH * DRAFT) / TANK  # at rest upright at Archimedes' draft
    centre = level - DRAFT + HEIGHT / 2
    heights, levels, angles = [], [], []
    samples, left = window_samples(scene, t_end, window, 0.05)
    for state, x in samples:
        heights.append(state.position[1])
        levels.append(x[np.abs(x[:, 0] - GAUGE) < dx, 1].max() + dx / 2)
        angles.append(math.degrees(state.orientation + roll))  # the body's angle is from its release
    y, surface = np.mean(heights), np.mean(levels)
    return {"draft": (surface - (y - HEIGHT / 2)) / DRAFT - 1, "centre": (y - centre) / DRAFT,
            "level": (surface - level) / dx, "roll": abs(np.mean(angles)), "largest roll": np.max(np.abs(angles)),
            "bobbing": np.std(heights) / dx, "lost": fluid - left}


def check(found, bar):
    """The draft and the centre height within `bar` of Archimedes' (relative to d_A), the
    level at the gauge within 0.15 dx of the mass balance's, no water lost, settled (the
    centre's deviation below 0.1 dx), upright: the mean roll below 0.75 deg, none above 1.5."""
    print({key: round(float(value), 4) for key, value in found.items()})
    assert found["lost"] == 0
    assert abs(found["draft"]) < bar
    assert abs(found["centre"]) < bar
    assert abs(found["level"]) < 0.15
    assert found["bobbing"] < 0.1
    assert found["roll"] < 0.75
    assert found["largest roll"] < 1.5


@pytest.mark.parametrize("release", list(RELEASES))
def test_a_released_box_settles_at_archimedes_draft_quick(release):
    """dx = 0.05 m (d_A = 5 dx), 6 s, means over 4-6 s. Measured (draft and centre height:
    % of d_A, the centre's + above the mass balance's; level: dx; roll: deg): deeper -0.55,
    +0.37, -0.009, 0; higher -0.06, +0.10, +0.002, 0; rolled -3.3, +3.1, -0.010, 0.23
    (largest 0.48; rolled -15 deg and +10 deg instead, means over 4.2-6 s: draft -3.1 % and -2.3 %, roll
    0.23 and 0.26 deg). The centre's bobbing over the window 0.004-0.015 dx. Bars: 3 % (heave),
    5 % (roll: the first water layer's packing, module docstring). About 12 s each on 2
    cores."""
    check(settle(0.05, release, 6.0, 2.0), 0.05 if release == "rolled" else 0.03)


@pytest.mark.slow
@pytest.mark.parametrize("release", list(RELEASES))
def test_a_released_box_settles_at_archimedes_draft(release):
    """dx = 0.025 m (d_A = 10 dx), 8 s, means over 5-8 s. Measured (as in the quick test):
    deeper -0.10, +0.17, +0.007, 0; higher -0.41, +0.09, -0.032, 0.01; rolled -0.56, +1.2,
    +0.064, 0.17 (largest 0.56); bobbing 0.006-0.026 dx. Bar 2.5 % (twice the largest
    error, the rolled box's centre). 81-93 s each on 2 cores."""
    check(settle(0.025, release, 8.0, 3.0), 0.025)


@pytest.mark.slow
@pytest.mark.parametrize("release", list(RELEASES))
def test_the_bars_catch_a_9_percent_buoyancy_error(release):
    """The quick test's runs with a box of 545 kg/m^3 (9 % heavier than the 500 kg/m^3 its
    d_A is computed for: what a buoyancy 9 % too weak would give) miss the quick test's
    draft bar (3 %, rolled 5 %). Measured (draft, centre: % of d_A; level: dx): deeper
    +8.5, -4.9, +0.18; higher +8.4, -5.2, +0.16; rolled +6.5, -2.6, +0.20 (the level's bar,
    0.15 dx, fails too). 10-13 s each."""
    found = settle(0.05, release, 6.0, 2.0, density=1.09 * DENSITY)
    print({key: round(float(value), 4) for key, value in found.items()})
    assert found["draft"] > (0.05 if release == "rolled" else 0.03)


CUBE, CUBE_TANK, CUBE_DEPTH = 0.4, 1.0, 0.6  # tests/test_bodies.py's 3D floating cube
CUBE_DRAFT = DENSITY / RHO_WATER * CUBE  # Archimedes: 0.2 m


def settle_cube(dx, t_end, window, density=DENSITY) -> dict:
    """The 3D cube of tests/test_bodies.py (0.4 m of 500 kg/m^3 in a 1 m square tank of
    water 0.6 m deep) let go upright with its bottom 1.4 d_A below the still surface, run
    to `t_end`; over the last `window` seconds (every 0.1 s) the means of the draft (the
    gauge's level at x = 0.15 m, z = 0.5 m less the cube's bottom) and of its centre
    height against the mass balance's (level L = (V + b^2 d_A) / W^2, V = N_fluid dx^3),
    relative to d_A, the largest tilt (deg) and the fluid particles lost."""
    scene = taisph.cases.floating_box(dim=3, dx=dx, tank_width=CUBE_TANK, depth=CUBE_DEPTH, box_width=CUBE,
                                      box_height=CUBE, box_density=density, box_bottom=CUBE_DEPTH - 1.4 * CUBE_DRAFT,
                                      t_end=t_end, frames=0)
    fluid = int(np.sum(scene.kind == 0))
    level = (fluid * dx**3 + CUBE**2 * CUBE_DRAFT) / CUBE_TANK**2
    centre = level - CUBE_DRAFT + CUBE / 2
    drafts, heights, tilts = [], [], []
    samples, left = window_samples(scene, t_end, window, 0.1)
    for state, x in samples:
        column = x[(np.abs(x[:, 0] - 0.15) < dx) & (np.abs(x[:, 2] - 0.5) < dx)]
        drafts.append(column[:, 1].max() + dx / 2 - (state.position[1] - CUBE / 2))
        heights.append(state.position[1])
        tilts.append(math.degrees(2 * math.acos(min(1.0, abs(state.orientation[0])))))
    found = {"draft": np.mean(drafts) / CUBE_DRAFT - 1, "centre": (np.mean(heights) - centre) / CUBE_DRAFT,
             "tilt": max(tilts), "lost": fluid - left}
    print({key: round(float(value), 4) for key, value in found.items()})
    return found


def test_a_released_cube_settles_at_archimedes_draft_in_3d():
    """Archimedes in 3D from away from the answer (issue 51, item 9; the slow
    tests/test_bodies.py cube starts at its draft): dx = 0.05 m (d_A = 4 dx, 4 416 fluid
    particles), let go 40 % deeper, 3 s, means over 2-3 s. Measured 2026-12-07 (a 4 s run,
    `python /tmp/s51/cube3d.py 0.05 4.0 1.4`): the draft overshoots to -14 % at 0.6 s,
    rings down to within 1.5 % by 1.6 s and sits at -1.4 to -1.7 % over 3-4 s; this test:
    draft -0.73 %, centre +0.16 % of d_A, no tilt, 155 s of CPU (2.6 min at load 7). Bars: the draft and the centre height within 3 % of d_A (the 2D
    heave bar, about four times the measured), no water lost, tilt below 0.5 deg. A
    buoyancy 9 % too weak moves the draft by +9 % (the 2D runs: +8.5 %), far outside."""
    found = settle_cube(0.05, 3.0, 1.0)
    assert found["lost"] == 0
    assert abs(found["draft"]) < 0.03
    assert abs(found["centre"]) < 0.03
    assert found["tilt"] < 0.5
