"""The rising bubble of Hysing et al. (2009, Int. J. Numer. Meth. Fluids 60:1259) against the
benchmark's quantities (taisph.validation.phases.HYSING_1, HYSING_2; docs/multiphase.md).

Test case 1 (density ratio 10, viscosity ratio 10, sigma 24.5): the maximum rise velocity
0.2417 at t = 0.921, the centre of mass 1.081 at t = 3, the minimum circularity 0.9013.
Test case 2 (density ratio 1000, viscosity ratio 100, sigma 1.96): the run holds, each
phase keeps its mass, the first rise-velocity maximum is near 0.25 at t = 0.73.
"""

import numpy as np
import pytest

from taisph.validation.phases import HYSING_1, HYSING_2, rising_bubble_history


def _first_maximum(time, velocity, before):
    """(value, time) of the rise velocity's largest sample before `before` s."""
    sel = time <= before
    k = int(np.argmax(velocity[sel]))
    return float(velocity[sel][k]), float(time[sel][k])


def test_rising_bubble_test_case_1_quick():
    """dx = 1/40 (the bubble 20 particles across), to t = 1.2: each phase's mass exact; the
    rise velocity's maximum comes at the benchmark's time within its 5 % (measured 2026-12-08,
    `python -m pytest tests/test_rising_bubble.py -m "not slow"`, and the same sampled every 0.02 s
    to t = 3 by `rising_bubble_history(1/40)`: 0.2190 at t = 0.90, -2.3 %) and its value within
    15 % (-9.4 %; at dx = 1/80 -8.3 %: the slow test's 5 % is a strict xfail)."""
    h = rising_bubble_history(1.0 / 40.0, test_case=1, t_end=1.2, every=0.02, circularity=False)
    assert np.array_equal(h["mass"][0], h["mass"][1])
    v_max, t_max = _first_maximum(h["time"], h["velocity"], 1.2)
    assert t_max == pytest.approx(HYSING_1["time_of_max"], rel=0.05)
    assert v_max == pytest.approx(HYSING_1["max_rise_velocity"], rel=0.15)


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="measured 2026-12-08 at dx = 1/80: rise velocity maximum 0.2216 at t = 0.90 "
                                       "(-8.3 %), centre at t = 2.9 1.0011 (1/40: 1.0309 at t = 3, -4.6 %): the "
                                       "bubble rises too slowly and refining does not close the gap "
                                       "(docs/multiphase.md)")
def test_rising_bubble_test_case_1_converges():
    """dx = 1/80 (40 particles across the bubble), to t = 3: the benchmark's bars, rise
    velocity maximum within 5 % in value and time, centre at t = 3 within 2 %, minimum
    circularity within 2 %."""
    h = rising_bubble_history(1.0 / 80.0, test_case=1, t_end=3.0, every=0.02)
    assert np.array_equal(h["mass"][0], h["mass"][1])
    v_max, t_max = _first_maximum(h["time"], h["velocity"], 1.2)
    assert v_max == pytest.approx(HYSING_1["max_rise_velocity"], rel=0.05)
    assert t_max == pytest.approx(HYSING_1["time_of_max"], rel=0.05)
    assert h["centre"][-1] == pytest.approx(HYSING_1["centre_at_3"], rel=0.02)
    assert h["circularity"].min() == pytest.approx(HYSING_1["min_circularity"], rel=0.02)


def test_rising_bubble_density_ratio_1000_holds():
    """Test case 2 (air-water-like, ratio 1000) at dx = 1/20, to t = 0.5 s: no guard trips,
    each phase's mass is exact, and the bubble rises and accelerates (measured 2026-12-08:
    centre 0.5 -> 0.552, rise velocity 0.184 at t = 0.5; 32 s)."""
    h = rising_bubble_history(1.0 / 20.0, test_case=2, t_end=0.5, every=0.05, circularity=False)
    assert np.array_equal(h["mass"][0], h["mass"][1])
    assert h["centre"][-1] > 0.53
    assert 0.1 < h["velocity"][-1] < 0.3


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="measured 2026-12-08 at dx = 1/40: the density guard stops the run at t = 0.44 s "
                                       "(a liquid particle above the bubble stretched by 20 %); an earlier build "
                                       "(normals reliable above 0.2/h instead of 0.05/h) ran to t = 0.8 s with its "
                                       "first maximum 0.237 at t = 0.6 (docs/multiphase.md)")
def test_rising_bubble_test_case_2_first_maximum():
    """Test case 2 at dx = 1/40, to t = 1: the first rise-velocity maximum within 10 % of the
    benchmark's 0.25 near t = 0.73 (as the issue quotes the reference solutions)."""
    h = rising_bubble_history(1.0 / 40.0, test_case=2, t_end=1.0, every=0.02, circularity=False)
    assert np.array_equal(h["mass"][0], h["mass"][1])
    v_max, t_max = _first_maximum(h["time"], h["velocity"], 1.0)
    assert v_max == pytest.approx(HYSING_2["first_max_rise_velocity"], rel=0.10)
