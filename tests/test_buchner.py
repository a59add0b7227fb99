"""The 2D dam break of Zhou/Buchner (cases/dam_break_probes_2d.toml, H = 0.6 m, 1.2 m
column, 3.22 m tank) against Buchner's (2002) wall pressures P1 and P2, measured by the
scene file's probes (docs/validation.md: the comparison, the sensor model, the plot)."""

import math

import numpy as np
import pytest

from taisph.validation import buchner


def test_metrics_of_the_experiment_against_itself():
    """The experiment compared with itself: no error, P1's impact (P = 0.1) at
    T = 2.478 between its samples at 2.473 (0.077) and 2.491 (0.154); a signal higher
    by 0.1 everywhere has a mean absolute error of 0.1; a sensor that reads no value
    (dry, NaN) counts as P = 0, so an all-dry signal's error is the mean of |P_exp|."""
    T, P = buchner.reference("P1")
    m = buchner.compare(T, P, "P1")
    assert m["mae"] == 0 and m["impact_T"] == m["impact_T_ref"]
    assert m["impact_T"] == pytest.approx(2.47263 + (0.1 - 0.07666) / (0.15352 - 0.07666) * (2.49148 - 2.47263))
    assert buchner.compare(T, P + 0.1, "P1")["mae"] == pytest.approx(0.1)
    inside = (T >= 2) & (T <= 6)
    dry = buchner.compare(T, np.full_like(P, np.nan), "P1")
    assert dry["mae"] == pytest.approx(np.abs(P[inside]).mean()) and math.isnan(dry["impact_T"])


def test_probe_noise_measures_ringing_not_the_load():
    """The noise figure (rms of P minus its 0.02-T moving average after the impact): a
    smooth load reads 0 (a ramp, to round-off); a ringing of amplitude A
    and period 0.004 in T (five periods per window, so the average removes it) reads
    A / sqrt(2) within 2 %; unevenly spaced samples (an adaptive step) give the same."""
    rng = np.random.default_rng(3)
    T = np.sort(np.concatenate([np.linspace(2.0, 6.0, 40001), rng.uniform(2.0, 6.0, 5000)]))
    load = np.clip(T - 2.4, 0.0, None)
    assert buchner.compare(T, load, "P1")["noise"] < 1e-7
    A = 0.2
    ringing = buchner.compare(T, load + A * np.sin(2 * np.pi * T / 0.004), "P1")
    assert ringing["noise"] == pytest.approx(A / math.sqrt(2), rel=0.02)
    assert ringing["peak"] == pytest.approx(6.0 - 2.4 - 0.005, abs=1e-3)  # at T = 6 the window is [5.99, 6]


def test_p1_impact_time_at_coarse_resolution():
    """dx = 0.03 m (H/dx = 20) to T = 3.2, the example's settings: the surge reaches
    P1 (P = 0.1 rho g H) within 5 % of the experiment's T = 2.478 (measured T = 2.550,
    +2.9 %; with the pressure at the sensor's middle instead of its face, 2.644, +6.7 %);
    before the surge arrives (T < 2.3) both sensors are dry: they read no value."""
    result = buchner.run(dx=0.03, t_end=3.2 / math.sqrt(buchner.G / buchner.H))
    assert result["stopped"] == ""
    assert abs(result["P1"]["impact_error"]) < 0.05, result["P1"]
    for sensor in ("P1", "P2"):
        T, P = result[f"{sensor}_series"]
        assert np.all(np.isnan(P[T < 2.3])) and not np.all(np.isnan(P))


@pytest.mark.slow
@pytest.mark.parametrize("dx, mae_bar, impact_bar", [(0.02, 0.14, 0.03), (0.01, 0.10, 0.015)])
def test_p1_and_p2_against_buchner(dx, mae_bar, impact_bar):
    """The example's settings with the symmetric form (seed eqs. 7-8, the example's until
    issue 26) to T = 6.1 (dx = 0.02 m: 35 s, 0.01 m: 4 min on 2 cores): no guard stops the
    run; against the experiment, P1's mean absolute error over T in [2, 6] at most 0.14
    rho g H at dx = 0.02 and 0.10 at 0.01 (measured 0.114 and 0.080; published delta-SPH:
    0.10-0.12), its impact time within 3 % and 1.5 % of the experiment's (measured +1.3 %
    and -0.5 %), P2's error at most 0.05 (0.033 and 0.029). Measured for issue 51 (100 s and
    510 s on 2 busy cores; docs/validation.md: 0.114, 0.080)."""
    result = buchner.run(dx=dx, overrides={"physics.formulation": "symmetric"})
    print(f"dx {dx}: P1 {result['P1']}, P2 MAE {result['P2']['mae']:.3f}")
    assert result["stopped"] == ""
    assert abs(result["P1"]["impact_error"]) < impact_bar, result["P1"]
    assert result["P1"]["mae"] <= mae_bar, result["P1"]
    assert result["P2"]["mae"] <= 0.05, result["P2"]


def test_p1_and_p2_under_dfsph():
    """The same scene file under DFSPH (its Courant number 0.125 is WCSPH's: DFSPH's 0.5
    instead) at dx = 0.03 to T = 6.1: no guard stops it; P1's impact within 5 % of the
    experiment's, P1's mean absolute error over T in [2, 6] at most 0.15 rho g H (issue 25's
    bar) and P2's at most 0.05; P1's probe noise at most 0.05 (issue 26's bar). Measured
    for issue 51: P1 0.090, impact +2.2 %, P2 0.024, noise 0.019 (2026-12-03, before DFSPH's
    still-water change: 0.106, +2.2 %, 0.024, 0.018; at dx = 0.02: 0.095, +1.0 %, 0.018;
    docs/dfsph.md, "What accuracy costs")."""
    result = buchner.run(dx=0.03, overrides={"solver": "dfsph"}, courant=0.5)
    assert result["stopped"] == ""
    assert abs(result["P1"]["impact_error"]) < 0.05, result["P1"]
    assert result["P1"]["mae"] <= 0.15, result["P1"]
    assert result["P2"]["mae"] <= 0.05, result["P2"]
    assert result["P1"]["noise"] <= 0.05, result["P1"]


def test_p1_and_p2_with_the_riemann_formulation():
    """The scene file with physics.formulation = "riemann" (alpha and delta 0, Zhang, Hu &
    Adams 2017) at dx = 0.03 to T = 6.1: no guard stops it; P1's impact within 5 % of the
    experiment's, its mean absolute error at most 0.15 rho g H and P2's at most 0.05, as
    for the symmetric form; and P1's ringing, the probe noise, at most 0.05 rho g H (issue
    26's bar; held here at 0.02, about 3x the measured). Measured (2026-12-03, and again for
    issue 51): P1 0.132, impact +3.5 %, noise 0.007, P2 0.023 (the symmetric form:
    0.122, 0.017, 0.043; docs/validation.md, "What sets the wall pressure")."""
    result = buchner.run(dx=0.03, overrides={"physics.formulation": "riemann", "physics.alpha": 0.0,
                                             "physics.delta": 0.0})
    assert result["stopped"] == ""
    assert abs(result["P1"]["impact_error"]) < 0.05, result["P1"]
    assert result["P1"]["mae"] <= 0.15, result["P1"]
    assert result["P2"]["mae"] <= 0.05, result["P2"]
    assert result["P1"]["noise"] <= 0.02, result["P1"]


AS_SHIPPED_REFINED_MISSES = pytest.mark.xfail(strict=True, reason=(
    "a known miss: at dx = 0.01 the example as shipped times P1's impact +5.4 % late, outside the 5 % bar dx = 0.02 "
    "meets (+2.5 %; MAE 0.086, noise 0.004, P2 0.029 within theirs); docs/validation.md, 'What sets the wall "
    "pressure': buchner.run(dx=0.01), 429 s"))


@pytest.mark.slow
@pytest.mark.parametrize("dx", [0.02, pytest.param(0.01, marks=AS_SHIPPED_REFINED_MISSES)])
def test_the_example_as_shipped_against_buchner(dx):
    """The example as shipped (the Riemann formulation with alpha 0.02 and delta 0.1) to
    T = 6.1, against the experiment: P1's impact within 5 % (measured +2.5 % at dx = 0.02),
    its mean absolute error at most 0.15 (0.123) and its probe noise at most 0.03 (0.011);
    P2 at most 0.05 (0.024); 141 s on 2 busy cores. At dx = 0.01 (the same bars, a strict
    xfail) the impact is +5.4 % late (MAE 0.086, noise 0.004; docs/validation.md, "What
    sets the wall pressure"; 429 s)."""
    result = buchner.run(dx=dx)
    print(f"dx {dx}: P1 {result['P1']}, P2 MAE {result['P2']['mae']:.3f}")
    assert result["stopped"] == ""
    assert abs(result["P1"]["impact_error"]) < 0.05, result["P1"]
    assert result["P1"]["mae"] <= 0.15, result["P1"]
    assert result["P1"]["noise"] <= 0.03, result["P1"]
    assert result["P2"]["mae"] <= 0.05, result["P2"]


# the scene files' defaults where the example tunes its own (docs/scenes.md): the cubic spline with
# h = 1.3 dx, the Riemann formulation without alpha or delta (its defaults), Courant 0.25
SCENE_FILE_DEFAULTS = {"kernel": "spline", "h_factor": 1.3, "physics.formulation": "riemann",
                       "physics.alpha": 0.0, "physics.delta": 0.0}


@pytest.mark.slow
def test_the_scene_files_defaults_against_buchner():
    """Issue 26's bar, P1 and P2 within a mean absolute error of 0.10 rho g H with the
    scene files' defaults instead of the example's tuned settings, at dx = 0.005 m
    (H/dx = 120; ~1 000 s on one thread): no guard stops the run, P1's impact within 5 %,
    its probe noise at most 0.05. Measured (2026-12-06, `python -m
    tools.studies.wall_pressure --dx D --only defaults+riemann`): P1 0.124, 0.107 and 0.086
    at dx = 0.02, 0.01 and 0.005 (a measure that converges), P2 0.033, noise 0.026, impact
    +2.9 %; at the coarser two the bar is missed (docs/validation.md, "Where the defaults'
    P1 error lies")."""
    result = buchner.run(dx=0.005, overrides=SCENE_FILE_DEFAULTS, courant=0.25)
    assert result["stopped"] == ""
    assert abs(result["P1"]["impact_error"]) < 0.05, result["P1"]
    assert result["P1"]["mae"] <= 0.10, result["P1"]
    assert result["P2"]["mae"] <= 0.10, result["P2"]
    assert result["P1"]["noise"] <= 0.05, result["P1"]
