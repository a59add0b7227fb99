"""The cylinder benchmark of Schaefer & Turek (1996), case 2D-1 (Re 20): cases/cylinder.py
against the reference drag, lift and pressure difference (docs/validation.md, "Flow past a
cylinder"). The measured values quoted below come from the study there."""

import math
import subprocess
import sys

import numpy as np
import pytest

import taisph
from taisph.probes import Probes
from taisph.validation.cylinder import REFERENCE_RE100, coefficients, probe_table, window_means

REFERENCE = {"C_D": 5.5795, "C_L": 0.0106, "dp": 0.1175}  # Schaefer & Turek (1996), Re 20
D, NU, RHO, H = 0.1, 1e-3, 1.0, 0.41


def run(dx, t_end, window, **params):
    """Run the case to `t_end`; the means of C_D, C_L and dp = p_front - p_back over the
    last `window` seconds, and the simulation's health at the end."""
    scene = taisph.cases.cylinder(dx=dx, t_end=t_end, **params)
    re = params.get("re", 20.0)
    u_mean = re * NU / D
    probes = Probes(scene.probes, walls=scene.wall_groups)
    sim = taisph.Simulation(scene)
    inlet0 = np.count_nonzero(sim.buffer & (sim.positions()[:, 0] < 0))
    mass0 = sim.masses()[sim.fluid].sum()
    sim.run(t_end, frames=0, writers=[probes])
    t, force = probes.series("cylinder")
    _, front = probes.series("p_front")
    _, back = probes.series("p_back")
    last = t > t_end - window
    q = 0.5 * RHO * u_mean**2 * D
    x = sim.positions()
    out = {"C_D": force[last, 0].mean() / q, "C_L": force[last, 1].mean() / q, "dp": (front - back)[last].mean(),
           "extra_inlet_buffer": np.count_nonzero(sim.buffer & (x[:, 0] < 0)) - inlet0,
           "fluid_in_walls": np.count_nonzero(sim.fluid & ((x[:, 1] < 0) | (x[:, 1] > H))),
           "mass_change": sim.masses()[sim.fluid].sum() / mass0 - 1.0, "mass_in": sim.open_boundary_mass()[0]}
    sim.close()
    return out


def test_the_scene_is_the_benchmark():
    """Geometry and flow of 2D-1: the cylinder's wall group is centred on (0.2, 0.2) with
    radius D/2 (its outer ring within dx of the circle), the
    fluid fills the channel outside it, the inflow peaks at 0.3 m/s, the probes are there."""
    dx = 0.01
    scene = taisph.cases.cylinder(dx=dx)
    body = scene.position[scene.wall_groups["cylinder"]]
    assert np.all(scene.kind[scene.wall_groups["cylinder"]] == taisph.WALL)
    assert np.allclose(body.mean(axis=0), (0.2, 0.2), atol=1e-12)  # symmetric about the centre
    r = np.linalg.norm(body - (0.2, 0.2), axis=1)
    assert r.max() < D / 2 and r.max() > D / 2 - dx
    fluid = scene.position[(scene.kind == taisph.FLUID) & (scene.quantities["open_zone"] == 0)]
    assert np.linalg.norm(fluid - (0.2, 0.2), axis=1).min() >= D / 2
    assert fluid[:, 0].min() > 0 and fluid[:, 0].max() < 2.2 and fluid[:, 1].min() > 0 and fluid[:, 1].max() < H
    assert len(fluid) == pytest.approx((2.2 * H - math.pi * D**2 / 4) / dx**2, rel=0.01)
    inlet = scene.open_boundaries[0]
    table, _ = inlet.table(2)
    assert table[-1, :, 0, 0].max() == pytest.approx(0.3, rel=1e-3) and table[0].max() == 0.0  # ramped from rest
    assert {p.name for p in scene.probes} == {"cylinder", "p_front", "p_back"}
    assert taisph.cases.cylinder(dx=dx, re=100).open_boundaries[0].table(2)[0][-1].max() == pytest.approx(1.5,
                                                                                                          rel=1e-3)


def test_the_command_line_writes_the_probes(tmp_path):
    """``python -m taisph cylinder --no-output`` runs the case with its own probes and
    wall group into OUT/probes.csv (a few steps at D/dx = 10)."""
    done = subprocess.run([sys.executable, "-m", "taisph", "cylinder", "--dx", "0.01", "--t-end", "0.02",
                           "--no-output", "--no-progress", "--out", str(tmp_path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    table = taisph.probes.read_csv(tmp_path / "probes.csv")
    assert {"cylinder_x", "cylinder_y", "p_front", "p_back"} <= set(table)
    assert len(table["time"]) > 2


def test_drag_at_coarse_resolution():
    """D/dx = 10, 4 s (the 1 s ramp, then the flow about the cylinder steady within the
    noise after ~2 s; its last 2 s averaged) with the case's defaults (rings, summed
    density, particle shifting, no background pressure). Measured 2026-12-07 (`pytest -n 0
    -s tests/test_cylinder.py -k drag_at_coarse` with a print, 247 s under load; 85 s on an
    idle thread): C_D 5.697 (+2.1 %), dp 0.11725 Pa (-0.2 %), C_L -0.034, the channel's mass
    +0.26 %, the mass in +0.24 % of the inflow's integral (the staircase before rings were
    the default: C_D +5.0 %, dp -3.4 %). The window means are noisy (`python
    /tmp/s51/cyl.py`, 2026-12-07, 244 s: the same run read over shorter windows): C_D +1.3 %
    and +2.9 % over 2-3 and 3-4 s, -2.3 to +5.0 % over half seconds (the 2 s mean's
    standard error ~1.6 %); dp +2.6 % and -3.0 % over seconds, -7.3 to +12.1 % over half
    seconds (standard deviation 9 %, ~4.5 % for the 2 s mean); the VM's processors differ
    in round-off, so the noise, not the 2 s mean's error, sets the bars. Asserted:
    - the drag within 7 % of the reference (3x the error; 2.1 % + 3 x 1.6 % noise);
    - the pressure difference front - back within 12 % of the reference (~3x its noise:
      the error itself, -0.2 %, is far below it);
    - the lift is small: |C_L| < 0.1 C_D (the channel is nearly symmetric; C_L's window
      noise is not measured, so this bar is not tightened);
    - the open boundaries work, the inlet's contract rather than the benchmark: the mass
      that entered is the prescribed inflow's integral 0.41 U (t - ramp/2) within 0.75 %
      (3x), the channel's mass stays within 0.75 % (3x), the inlet's buffer keeps its
      particles and no fluid leaks into the walls."""
    t_end = 4.0
    out = run(0.01, t_end, window=2.0)
    assert out["C_D"] == pytest.approx(REFERENCE["C_D"], rel=0.07), out
    assert out["dp"] == pytest.approx(REFERENCE["dp"], rel=0.12), out
    assert abs(out["C_L"]) < 0.1 * out["C_D"], out
    assert out["mass_in"] == pytest.approx(RHO * H * 0.2 * (t_end - 0.5), rel=0.0075), out
    assert abs(out["mass_change"]) < 0.0075, out
    assert out["extra_inlet_buffer"] == 0 and out["fluid_in_walls"] == 0, out


@pytest.mark.slow
def test_the_benchmark_bar_at_twenty_particles_per_diameter():
    """D/dx = 20 to t = 6 s, the last 2 s averaged: C_D within 5 % and dp within 10 % of
    Schaefer & Turek's: the issue's benchmark bars (the accuracy asked of the case at this
    resolution), kept as they are, not 3x bars of the measurement. Measured with the case's
    defaults (rings; 2026-12-06, 894 s on one thread): C_D 5.612 (+0.6 %), dp 0.1190 Pa
    (+1.3 %), C_L -0.008, mass +0.2 %. The means of single seconds swing: C_D 5.59, 5.66,
    5.62, 5.60 and dp 0.107, 0.131, 0.123, 0.115 Pa over 2-3, 3-4, 4-5, 5-6 s (the
    staircase's C_D 5.60, 5.66, 5.47, 5.88: a slow oscillation of the channel under the
    samples' noise), so the 2 s window matters. The channel's mass within 0.75 % (~3x the
    measured +0.2 %; the same bar as at D/dx = 10, where +0.26 % was measured twice;
    tightened 2026-12-07 from 1 % without a rerun)."""
    out = run(0.005, 6.0, window=2.0)
    assert out["C_D"] == pytest.approx(REFERENCE["C_D"], rel=0.05), out
    assert out["dp"] == pytest.approx(REFERENCE["dp"], rel=0.10), out
    assert abs(out["mass_change"]) < 0.0075, out
    assert out["extra_inlet_buffer"] == 0 and out["fluid_in_walls"] == 0, out


@pytest.mark.slow
def test_shedding_at_re_100_at_twenty_particles_per_diameter():
    """Schaefer & Turek's 2D-2 (Re 100, U_max = 1.5 m/s) with the case's defaults at
    D/dx = 20 to t = 6 s, read over the last 2 s (taisph.validation.cylinder.window_means:
    the Strouhal number from C_L's spectrum, the maxima over a period averaged at equal
    phase): St within 5 % of 0.295-0.305 and max C_D within 10 % of 3.22-3.24, the
    issue's bars. Measured (2026-12-06, one thread, 5 994 s; `cylinder_study --re 100`,
    docs/validation.md, "Re 100"): St 0.297, max C_D 3.51 (+8.7 %), max C_L 1.03, mean
    C_D 3.41 (still rising slowly: 3.31 over 2-4 s), mass -0.0 %. The longest test of the
    slow suite: 40 min to 1.7 h here (the staircase's run on two threads took 2 451 s)."""
    re, t_end = 100.0, 6.0
    scene = taisph.cases.cylinder(dx=0.005, re=re, t_end=t_end)
    probes = Probes(scene.probes, walls=scene.wall_groups)
    sim = taisph.Simulation(scene)
    mass0 = sim.masses()[sim.fluid].sum()
    sim.run(t_end, frames=0, writers=[probes])
    mass_change = sim.masses()[sim.fluid].sum() / mass0 - 1.0
    sim.close()
    m = window_means(coefficients(probe_table(probes), re), 2.0)
    st = m["St"] * D / (re * NU / D)
    low, high = REFERENCE_RE100["St"]
    assert 0.95 * low <= st <= 1.05 * high, m
    low, high = REFERENCE_RE100["C_D_max"]
    assert 0.90 * low <= m["C_D_max"] <= 1.10 * high, m
    assert abs(mass_change) < 0.01, mass_change
