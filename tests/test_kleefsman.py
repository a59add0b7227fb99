"""SPHERIC benchmark test 2 (Kleefsman et al. 2005): the 3D dam break against a box of
cases/dam_break_obstacle_3d.toml under DFSPH, against the MARIN experiment's pressures on
the box's front face and water heights (docs/validation.md, "SPHERIC test 2")."""

import math

import numpy as np
import pytest

from taisph.validation import kleefsman


def test_the_experiment_against_itself():
    """The reference compared with itself: no error; P1's impact (0.1 rho g H) at
    t = 0.393 s and its first peak (5 ms average) 1.95 rho g H, the 11.2 kPa at
    0.415 s the data hold; the surge reaches H2 (2 % of H) at 0.359 s; a signal higher by
    0.1 rho g H has a mean error of 0.1; a dry sensor (NaN) counts as 0."""
    ref = kleefsman.reference()
    t = ref["t"]
    m = kleefsman.compare_pressure(t, ref["P1"], "P1")
    assert m["mae"] == 0 and m["impact_error"] == 0 and m["peak_ratio"] == 1
    assert m["impact_t"] == pytest.approx(0.393, abs=0.001) and m["peak"] == pytest.approx(1.95, abs=0.01)
    assert ref["P1"].max() == pytest.approx(11239.4) and t[np.argmax(ref["P1"])] == pytest.approx(0.415, abs=1e-3)
    scale = kleefsman.RHO0 * kleefsman.G * kleefsman.H
    assert kleefsman.compare_pressure(t, ref["P1"] + 0.1 * scale, "P1")["mae"] == pytest.approx(0.1)
    h = kleefsman.compare_height(t, ref["H2"], "H2")
    assert h["mae"] == 0 and h["arrival_t"] == pytest.approx(0.359, abs=0.001)
    assert math.isnan(kleefsman.compare_height(t, ref["H4"], "H4")["arrival_t"])  # wet from the start
    dry = kleefsman.compare_height(t, np.full_like(t, np.nan), "H2")
    assert dry["mae"] == pytest.approx(np.mean(ref["H2"]) / kleefsman.H)


def test_surge_reaches_the_box_coarse():
    """dx = 0.04 m (10 500 fluid particles), DFSPH, to t = 1.2 s, through the impact on the
    box and the first 0.75 s of load on it (54 s on 2 cores at load ~6, 2026-12-07,
    ``kleefsman.run(dx=0.04, t_end=1.2, overrides={"solver": "dfsph"})``): the reservoir
    drains as measured (H4 within 0.06 H on average: measured 0.038 H, most of it the gauge
    reading the still surface 0.018 m = 0.033 H high at t = 0 at this dx); the surge
    reaches H2 and the box's P1 and P3 within 50 ms of the experiment (measured +39, +42
    and +26 ms: the coarse column's front is late; +28 and +31 ms at dx = 0.02 m); P3's
    pressure after its impact within 0.2 rho g H of the experiment on average (measured
    0.126; the slow test's bar at dx 0.02, where 0.108 was measured). P1's mean error at
    this dx (0.375) is not held: its first peak and the flow turning on the box's face
    need the finer run (docs/validation.md, SPHERIC test 2)."""
    out = kleefsman.run(dx=0.04, t_end=1.2, overrides={"solver": "dfsph"})
    assert out["stopped"] == ""
    assert out["H4"]["mae"] < 0.06, out["H4"]
    assert abs(out["H2"]["arrival_error"]) < 0.05, out["H2"]
    assert abs(out["P1"]["impact_error"]) < 0.05, out["P1"]
    assert abs(out["P3"]["impact_error"]) < 0.05, out["P3"]
    assert out["P3"]["mae"] < 0.2, out["P3"]


@pytest.mark.slow
def test_spheric2_at_dx_002():
    """dx = 0.02 m (82 350 fluid particles), DFSPH, to t = 2 s (5 min on 2 cores), against
    the experiment, bars of issue 26 for this case (the experiment is one repetition, so
    its scatter is not known; these are the measured values with a margin):
    water heights H2 and H4 within 0.05 H and 0.02 H on average (measured 0.037, 0.008);
    the mean pressure error after the impact on P1 and P3 within 0.2 rho g H (0.170, 0.108);
    impacts on P1 and P3 within 40 ms (+31, +24 ms); P3's first peak within 30 % (1.13
    against 1.20). P1's first peak is not held: 3.27 against 1.95 rho g H (docs/validation.md)."""
    out = kleefsman.run(dx=0.02, t_end=2.0, overrides={"solver": "dfsph"})
    assert out["stopped"] == ""
    assert out["H2"]["mae"] < 0.05 and out["H4"]["mae"] < 0.02, (out["H2"], out["H4"])
    for sensor in ("P1", "P3"):
        assert out[sensor]["mae"] < 0.2 and abs(out[sensor]["impact_error"]) < 0.04, out[sensor]
    assert abs(out["P3"]["peak_ratio"] - 1) < 0.3, out["P3"]
