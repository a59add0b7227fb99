"""Solitary wave (issue 28, check 5; cases/solitary_wave.py): a piston on Goring's (1978)
trajectory makes a solitary wave of H = 0.05 m in h = 0.14 m of water; at the gauges 1.5 m
and 2.5 m from the piston its crest is H and it runs at c = sqrt(g (h + H)) = 1.365 m/s."""

import math

import numpy as np
import pytest

import taisph
from taisph.cases.solitary_wave import GAUGES, expected, solitary_wave
from taisph.probes import Probes

DEPTH, HEIGHT = 0.14, 0.05


def crest(t, eta):
    """(time, height) of the highest sample of `eta` and its two neighbours' parabola's top."""
    k = int(np.nanargmax(eta))
    y0, y1, y2 = eta[k - 1:k + 2]
    s = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)  # the vertex, in samples from k (|s| <= 1/2)
    return t[k] + s * (t[k + 1] - t[k]), y1 - 0.25 * (y0 - y2) * s


def solitary_run(dx, **params):
    """Crest heights at the gauges over H and the celerity between them over sqrt(g (h + H)).
    (Not the piston's travel: its motion is prescribed, so its travel equals Goring's stroke
    by construction; the stroke is checked against sqrt(16 H h / 3) in
    tests/test_wave_makers.py, and what it is for, the wave, here.)"""
    scene = solitary_wave(dx=dx, depth=DEPTH, height=HEIGHT, **params)
    gauges = Probes([p for p in scene.probes if p.kind == "elevation"])
    sim = taisph.Simulation(scene)
    sim.run(scene.t_end, frames=1, writers=[gauges])
    t = np.asarray(gauges.times)
    crests = [crest(t, np.asarray(gauges.values[f"g{k + 1}"])) for k in range(len(GAUGES))]
    ex = expected(DEPTH, HEIGHT)
    heights = [(top - DEPTH) / HEIGHT for _, top in crests]
    celerity = (GAUGES[1] - GAUGES[0]) / (crests[1][0] - crests[0][0]) / ex["celerity"]
    sim.close()
    return heights, celerity


def test_expected_numbers():
    """Boussinesq's celerity sqrt(g (h + H)) and Goring's stroke sqrt(16 H h / 3)."""
    ex = expected(DEPTH, HEIGHT)
    assert ex["celerity"] == pytest.approx(math.sqrt(9.81 * 0.19))
    assert ex["stroke"] == pytest.approx(math.sqrt(16 * HEIGHT * DEPTH / 3))
    assert ex["crest_times"][0] < ex["crest_times"][1] < solitary_wave().t_end


def test_a_solitary_wave_runs_down_the_flume_quick():
    """Coarse (dx = 0.02 m = h/7, to 3.2 s). The crest, resolved by 2.5 particles, is low:
    measured 0.875 H and 0.799 H (2026-12-07); bar |height / H - 1| < 0.25 at both gauges
    (3x the measured 20 % would be 60 %: kept at 25 %; the issue's 5 % is the slow test's).
    The celerity between the gauges: measured 1.0019 sqrt(g (h + H)); bar |c / sqrt(g (h +
    H)) - 1| < 0.006, 3x the measured 0.19 % (was 0.03)."""
    heights, celerity = solitary_run(0.02, t_end=3.2)
    print(f"crests {heights}, celerity {celerity}")
    assert all(abs(x - 1.0) < 0.25 for x in heights), heights
    assert abs(celerity - 1.0) < 0.006, celerity


@pytest.mark.slow
def test_a_solitary_wave_keeps_its_height_and_celerity():
    """Issue 28, check 5, dx = 0.01 m = h/14, alpha = 0.01: crest within 5 % of H at both
    gauges, celerity within 3 % of sqrt(g (h + H)) (measured 1.0042 H and 0.9822 H, 1.0155 c,
    2026-12-07: both bars within 3x the measured errors, 1.8 % and 1.55 %)."""
    heights, celerity = solitary_run(0.01)
    print(f"crests {heights}, celerity {celerity}")
    assert all(abs(x - 1.0) < 0.05 for x in heights), heights
    assert abs(celerity - 1.0) < 0.03, celerity
