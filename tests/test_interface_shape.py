"""The shape of a phase's region from particles (taisph.validation.interface): the colour
field, its level-1/2 contour by marching squares and Hysing et al.'s (2009) circularity
c = 2 sqrt(pi A) / P, checked against exact geometry.

The shapes are particle lattices (spacing dx, cell-centred, volume dx^2 each) whose
particles inside the shape are of the phase; h = 1.3 dx (the rising bubble's default)
unless a test says otherwise, grid spacing dx / 4. A lattice's edge is a staircase, which
the kernel (support 2h = 2.6 dx) smooths into a contour with short wiggles: they make the
perimeter a little long, by an amount set by h / dx and by how the lattice meets the shape,
not by the grid (dx / 8 and dx / 4 grids measure the same). Circles of radius 10, 15, 19.7,
20, 20.3 and 40 dx at h = 1.3 dx measure P +1.02, +1.95, +1.03, +1.59, +0.38 and +0.96 %
(c 0.9928, 0.9872, 0.9889, 0.9872, 0.9936, 0.9902); the rising bubble's default, R = 10 dx,
is the first. Contours of known smooth fields check the marching squares alone.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from taisph.validation.interface import (bubble_circularity, circularity, colour_field, contour_length,
                                         contour_segments, cubic_spline_2d, enclosed_area)

DX = 0.025
H = 1.3 * DX


def lattice(nx: int, ny: int) -> np.ndarray:
    """nx x ny cell-centred points of spacing DX from the origin."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    return np.stack([(i.ravel() + 0.5) * DX, (j.ravel() + 0.5) * DX], axis=1)


def volumes(x):
    return np.full(len(x), DX * DX)


def circle_scene():
    """A circle of radius 20 dx in the middle of a 60 dx square box."""
    x = lattice(60, 60)
    radius = 20 * DX
    return x, np.hypot(*(x - 30 * DX).T) < radius, radius, (60 * DX, 60 * DX)


def ramanujan(a, b):
    """Ramanujan's (1914) approximation of an ellipse's perimeter (relative error ~1e-5 at a/b = 2)."""
    return math.pi * (3 * (a + b) - math.sqrt((3 * a + b) * (a + 3 * b)))


def test_the_kernel_is_the_engines_cubic_spline():
    """The module's own numpy spline is the engine's "spline" kernel in 2D (one kernel)."""
    from taisph.engine import smoothing

    spline = smoothing.KERNELS["spline"]()
    r = np.linspace(0.0, 2.5 * H, 101)
    assert np.allclose(cubic_spline_2d(r, H), spline.sigma(2) / H**2 * spline.f_numpy(r / H), rtol=1e-12, atol=0)


def test_a_circle_at_h_1_3_dx_has_its_perimeter_within_2_percent():
    """R = 20 dx, h = 1.3 dx: measured P = 1.0159 x 2 pi R (+1.59 %), A = sum V = 1.0059 pi R^2
    (the lattice's 1264 points inside against pi 400 = 1256.6), c = 0.9872."""
    x, phase, radius, hi = circle_scene()
    c, area, perimeter = circularity(x, volumes(x), phase, DX / 4, H, (0, 0), hi)
    assert perimeter == pytest.approx(2 * math.pi * radius, rel=0.02)
    assert area == pytest.approx(math.pi * radius**2, rel=0.01)
    assert c == pytest.approx(1.0, rel=0.015)


@pytest.mark.xfail(strict=True, reason="h = 1.3 dx: the lattice's staircase leaves wiggles on the contour, "
                                       "c = 0.9872 (1.28 % low); the 1 % bar holds from h = 1.5 dx (0.9921)")
def test_a_circle_at_h_1_3_dx_has_circularity_within_1_percent():
    """The brief's 1 % bar at the rising bubble's h = 1.3 dx: measured c = 0.9872."""
    x, phase, _, hi = circle_scene()
    c, _, _ = circularity(x, volumes(x), phase, DX / 4, H, (0, 0), hi)
    assert c == pytest.approx(1.0, rel=0.01)


def test_a_circle_at_h_2_dx_has_circularity_within_1_percent():
    """R = 20 dx, h = 2 dx (a smoother field, shorter wiggles): measured c = 0.9983,
    P = 1.0046 x 2 pi R (+0.46 %). (h = 1.5 dx: c = 0.9921, P +1.09 %.)"""
    x, phase, radius, hi = circle_scene()
    c, _, perimeter = circularity(x, volumes(x), phase, DX / 4, 2 * DX, (0, 0), hi)
    assert c == pytest.approx(1.0, rel=0.01)
    assert perimeter == pytest.approx(2 * math.pi * radius, rel=0.02)


def test_an_ellipse_has_ramanujans_perimeter_and_its_circularity():
    """Semi-axes a = 30 dx, b = 15 dx (a/b = 2), h = 1.3 dx: measured P = 1.0119 x Ramanujan's
    (+1.19 %), c = 0.9904 x 2 pi sqrt(ab) / P_Ramanujan (-0.96 %)."""
    x = lattice(80, 50)
    a, b = 30 * DX, 15 * DX
    d = x - (40 * DX, 25 * DX)
    phase = (d[:, 0] / a) ** 2 + (d[:, 1] / b) ** 2 < 1
    c, _, perimeter = circularity(x, volumes(x), phase, DX / 4, H, (0, 0), (80 * DX, 50 * DX))
    assert perimeter == pytest.approx(ramanujan(a, b), rel=0.02)
    assert c == pytest.approx(2 * math.pi * math.sqrt(a * b) / ramanujan(a, b), rel=0.02)


def test_a_square_has_four_sides_less_its_rounded_corners():
    """Side 40 dx, h = 1.3 dx: measured P = 0.9851 x 4 x side (-1.49 %): the corners round off
    (a radius r cuts (8 - 2 pi) r from the four corners: r = 1.4 dx = 1.07 h here); A = sum V = side^2 exactly."""
    x = lattice(60, 60)
    side = 40 * DX
    phase = (np.abs(x - 30 * DX) < side / 2).all(axis=1)
    c, area, perimeter = circularity(x, volumes(x), phase, DX / 4, H, (0, 0), (60 * DX, 60 * DX))
    assert perimeter == pytest.approx(4 * side, rel=0.03)
    assert perimeter < 4 * side
    assert area == pytest.approx(side**2, rel=1e-12)
    assert c == pytest.approx(2 * math.sqrt(math.pi) * side / perimeter, rel=1e-12)


def test_a_shape_across_a_periodic_boundary_measures_as_the_shifted_one():
    """A circle of radius 20 dx centred 3 dx from the left end of an x-periodic 80 dx box
    (40 % of it wraps to the right end) measures as the same circle in the
    middle: the perimeter, circularity and contour area agree to round-off (measured:
    P = 3.1916 m, c = 0.9872, contour area 1.0045 pi R^2 in both)."""
    x = lattice(80, 60)
    period, radius, hi = 80 * DX, 20 * DX, (80 * DX, 60 * DX)
    found = []
    for centre in (3 * DX, 40 * DX):
        d = x - (centre, 30 * DX)
        d[:, 0] -= period * np.round(d[:, 0] / period)
        phase = np.hypot(*d.T) < radius
        c, _, perimeter = circularity(x, volumes(x), phase, DX / 4, H, (0, 0), hi, periodic=(True, False))
        gx, gy, field = colour_field(x, volumes(x), phase, DX / 4, H, (0, 0), hi, periodic=(True, False))
        found.append((c, perimeter, enclosed_area(gx, gy, field)))
    assert found[0] == pytest.approx(found[1], rel=1e-9)
    assert found[0][1] == pytest.approx(2 * math.pi * radius, rel=0.02)
    assert found[0][2] == pytest.approx(math.pi * radius**2, rel=0.01)


def test_a_too_short_period_is_refused():
    x = lattice(4, 4)
    with pytest.raises(ValueError, match="periodic"):
        colour_field(x, volumes(x), np.ones(len(x), bool), DX / 4, H, (0, 0), (4 * DX, 4 * DX), (True, False))


def test_the_colour_field_is_one_inside_zero_outside_and_zero_out_of_reach():
    """Shepard's normalisation: 1 within the phase even at the particles' free edge, 0 in the
    other phase, 0 beyond every particle's reach; removed (NaN) particles are left out."""
    x = lattice(20, 20)
    phase = x[:, 0] < 10 * DX
    x = np.vstack([x, [[np.nan, np.nan]]])
    phase = np.append(phase, True)
    gx, gy, field = colour_field(x, volumes(x), phase, DX / 2, H, (0, 0), (30 * DX, 20 * DX))
    X, Y = np.meshgrid(gx, gy)
    assert field.shape == (len(gy), len(gx))
    assert np.allclose(field[X < 10 * DX - 2 * H], 1.0, rtol=0, atol=1e-12)  # corners and edges included
    assert np.allclose(field[X > 10 * DX + 2 * H], 0.0, rtol=0, atol=1e-12)
    assert np.all(field[X > 20 * DX + 2 * H] == 0.0)
    assert field.min() >= 0.0 and field.max() <= 1.0 + 1e-12


def test_marching_squares_on_a_smooth_field_converge_to_the_circle():
    """field = 1/2 + (R - r) on a 401 x 401 grid over [-1, 1]^2, R = 0.7: the contour is the
    circle r = R; measured length -3.1e-6 and area -1.1e-5 relative (an inscribed polygon's
    O((spacing / R)^2) shortfall)."""
    g = np.linspace(-1.0, 1.0, 401)
    X, Y = np.meshgrid(g, g)
    field = 0.5 + (0.7 - np.hypot(X, Y))
    assert contour_length(g, g, field) == pytest.approx(2 * math.pi * 0.7, rel=1e-4)
    assert enclosed_area(g, g, field) == pytest.approx(math.pi * 0.49, rel=1e-4)
    start, end = contour_segments(g, g, field)
    mid = (start + end) / 2 - 1.0  # segments are in coordinates relative to (gx[0], gy[0])
    tangent = end - start
    turning = mid[:, 0] * tangent[:, 1] - mid[:, 1] * tangent[:, 0]
    # inside on the left: counter-clockwise (4 nodes lie on r = R exactly, where the
    # segments of the two cells meeting there shrink to a point)
    assert np.all(turning[np.hypot(*tangent.T) > 0] > 0)


@pytest.mark.parametrize("corner, length, area", [
    # centre average (1 + 0.8) / 4 = 0.45 < 0.5: the two inside corners are cut apart,
    # segments (0.5, 0)-(0, 0.5) and (0.625, 1)-(1, 0.625)
    (0.8, math.sqrt(0.5) + 0.375 * math.sqrt(2), 0.125 + 0.5 * 0.375**2),
    # (1 + 1.2) / 4 = 0.55 > 0.5: joined through the centre, segments (0.5, 0)-(1, 5/12)
    # and (5/12, 1)-(0, 0.5); the area is the cell less the two outside corners' triangles
    (1.2, 2 * math.hypot(0.5, 5 / 12), 1 - 2 * 0.5 * 0.5 * 5 / 12),
])
def test_a_saddle_cell_is_resolved_by_its_centre(corner, length, area):
    """One cell, lower-left corner 1, upper-right `corner`, the other two 0, level 1/2."""
    field = np.array([[1.0, 0.0], [0.0, corner]])
    assert contour_length([0, 1], [0, 1], field) == pytest.approx(length, rel=1e-12)
    assert enclosed_area([0, 1], [0, 1], field) == pytest.approx(area, rel=1e-12)


def test_bubble_circularity_reads_a_simulation():
    """From a Simulation's arrays: fluid particles only (a wall row of the bubble's material
    changes nothing), volumes m / rho, the scene's box, periodicity and h, grid dx / 4."""
    x, phase, _, hi = circle_scene()
    walls = np.column_stack([np.arange(60) * DX, np.full(60, 30 * DX)])  # across the bubble: must be left out
    rho = np.where(phase, 100.0, 1000.0)
    sim = SimpleNamespace(
        positions=lambda: np.vstack([x, walls]), masses=lambda: np.append(rho * DX**2, np.full(60, 1000 * DX**2)),
        density=lambda: np.append(rho, np.full(60, 1000.0)),
        materials=lambda: np.append(phase.astype(int), np.ones(60, int)),
        fluid=np.append(np.ones(len(x), bool), np.zeros(60, bool)),
        scene=SimpleNamespace(domain=(np.zeros(2), np.array(hi)), periodic=(False, False), smoothing_length=H, dx=DX))
    assert bubble_circularity(sim) == pytest.approx(circularity(x, volumes(x), phase, DX / 4, H, (0, 0), hi),
                                                    rel=1e-12)
    liquid = bubble_circularity(sim, material=0)
    assert liquid[1] == pytest.approx((60 * 60 - phase.sum()) * DX**2, rel=1e-12)
