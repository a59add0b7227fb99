"""Reading regular waves off wave gauges (taisph/validation/waves.py): on an exact
progressive wave the height, phase and wavelength come back to the sampling's accuracy,
and the reading window starts after the ramped train's full part arrives and ends before
the far wall's reflection returns."""

import math

import numpy as np
import pytest

from taisph.cases.wave_flume import expected
from taisph.validation import waves

DEPTH, HEIGHT, PERIOD = 0.5, 0.04, 1.5
SAMPLING = (2 * math.pi / PERIOD * 0.01) ** 2 / 8  # a height read from samples 10 ms apart: at most this low


def progressive(xs, t, height=HEIGHT, period=PERIOD, depth=DEPTH):
    """eta(x, t) = depth + H/2 cos(k x - omega t), first-order theory's k."""
    k = expected(depth, height, period)["k"]
    w = 2 * math.pi / period
    return {f"g{n + 1}": depth + 0.5 * height * np.cos(k * x - w * t) for n, x in enumerate(xs)}


def test_expected_numbers_of_the_issues_wave():
    """kh = 1.112, wavelength 2.83 m, H/S = 1.082 (issue 28, check 4; measured 1.1115, 2.8265,
    1.08205): kh within 1e-3 (the issue rounded 1.1115 up), the others to their digits (5e-3
    and 5e-4); c_g between c/2 and c."""
    th = expected(DEPTH, HEIGHT, PERIOD)
    assert th["kh"] == pytest.approx(1.112, abs=1e-3)
    assert th["wavelength"] == pytest.approx(2.83, abs=5e-3)
    assert th["ratio"] == pytest.approx(1.082, abs=5e-4)
    assert 0.5 * th["celerity"] < th["group"] < th["celerity"]


def test_an_exact_wave_is_read_back():
    """Sampled every 10 ms at 1, 2 and 3 m: heights within (omega dt)^2 / 8 = 2.2e-4 (a crest
    or trough falls at most half a sample from one; measured 3.8e-5 at most; was 1e-3), the
    wavelength to round-off, 1e-12 (measured 2e-16; was 1e-6)."""
    xs = (1.0, 2.0, 3.0)
    t = np.arange(0.0, 12.0, 0.01)
    got = waves.measure(t, progressive(xs, t), xs, height=HEIGHT, period=PERIOD, depth=DEPTH, ramp=1.0,
                        length=10.0, t_end=12.0)
    assert got["heights"] == pytest.approx([1.0] * 3, abs=SAMPLING)
    assert got["wavelength"] == pytest.approx(1.0, abs=1e-12)
    assert all(n >= 2 for n in got["periods"])


def test_a_wave_of_another_length_is_told_apart():
    """A wave 5 % longer than theory's reads 1.05 to 1e-12 (measured 2e-15; the measure does not
    assume theory's k), its height 0.5 H within 0.5 (omega dt)^2 / 8 = 1.1e-4 (measured 9.2e-5)."""
    xs = (1.0, 2.0, 3.0)
    t = np.arange(0.0, 12.0, 0.01)
    k = expected(DEPTH, HEIGHT, PERIOD)["k"] / 1.05
    gauges = {f"g{n + 1}": DEPTH + 0.01 * np.cos(k * x - 2 * math.pi / PERIOD * t) for n, x in enumerate(xs)}
    got = waves.measure(t, gauges, xs, height=HEIGHT, period=PERIOD, depth=DEPTH, ramp=1.0, length=10.0,
                        t_end=12.0)
    assert got["wavelength"] == pytest.approx(1.05, abs=1e-12)
    assert got["heights"] == pytest.approx([0.5] * 3, abs=0.5 * SAMPLING)


def test_a_short_wave_between_distant_gauges_is_read():
    """T = 1.0 s (wavelength 1.513 m) at gauges 1 m apart: the phase advances 4.15 rad from
    gauge to gauge, more than pi; unwrapped about theory's k x it reads 1 to 1e-12 (measured
    9e-16; plain unwrapping read 1.92)."""
    xs = (1.0, 2.0, 3.0)
    t = np.arange(0.0, 12.0, 0.01)
    got = waves.measure(t, progressive(xs, t, height=0.03, period=1.0), xs, height=0.03, period=1.0, depth=DEPTH,
                        ramp=1.0, length=6.0, t_end=12.0, absorber=True)
    assert expected(DEPTH, 0.03, 1.0)["kh"] == pytest.approx(2.076, abs=5e-4)  # 2.0764, to its digits
    assert got["wavelength"] == pytest.approx(1.0, abs=1e-12)


def test_window_starts_after_the_train_and_ends_before_the_reflection():
    """start = ramp T + x / c_g + T; end = (2 L - x) / c without an absorber, rounded down
    to whole periods; with an absorber the record's end."""
    th = expected(DEPTH, HEIGHT, PERIOD)
    start, end = waves.window(2.0, PERIOD, DEPTH, 1.0, 6.0, 30.0)
    assert start == pytest.approx(PERIOD + 2.0 / th["group"] + PERIOD)
    assert end <= (12.0 - 2.0) / th["celerity"] < end + PERIOD
    assert (end - start) / PERIOD == pytest.approx(round((end - start) / PERIOD))
    _, end = waves.window(2.0, PERIOD, DEPTH, 1.0, 6.0, 30.0, absorber=True)
    assert 30.0 - PERIOD < end <= 30.0


def test_no_whole_period_is_refused():
    t = np.arange(0.0, 4.0, 0.01)
    with pytest.raises(ValueError, match="gauge g1 at x = 1 m: no whole period"):
        waves.measure(t, progressive((1.0,), t), (1.0,), height=HEIGHT, period=PERIOD, depth=DEPTH, ramp=1.0,
                      length=10.0, t_end=4.0)


def flume(dx):
    from taisph.validation import run

    out = run("wave_flume", dx=dx, length=6.0, absorber=2.5, t_end=8.5)
    assert not out.diverged
    return [out.metrics[f"g{k}_height"] for k in (1, 2, 3)], out.metrics["wavelength"], out.metrics["periods"]


def test_the_piston_makes_theorys_waves_quick():
    """The wave flume (issue 28, check 4) coarse (dx = 0.04 m: depth / dx = 12.5, H / dx =
    1; a 6 m flume with a 2.5 m sponge, to 8.5 s; the case's Wendland kernel, h = 2 dx).
    Measured (2026-12-07): wave heights 0.960, 0.923, 0.927 of first-order theory's H at the
    gauges 1, 2 and 3 m from the piston, wavelength 0.9987 of the dispersion relation's.
    Bars: heights within 10 % of H (the issue's bar; 3x the measured 7.7 % would be 23 %),
    wavelength within 0.4 % (3x the measured 0.13 %; was 2 %). A 7.7 % height error cannot
    tell Biesel's transfer H/S = 1.082 at kh = 1.112 from the shallow-water H/S = kh (2.7 %
    off); tests/test_wave_makers.py does: the transfer against Dean & Dalrymple's formula
    (rel 1e-12) and 1.082 (abs 5e-4), and the piston's stroke against H over it (rel 1e-12),
    each fail with H/S = kh."""
    heights, wavelength, periods = flume(0.04)
    print(f"heights {heights}, wavelength {wavelength}")
    assert heights == pytest.approx([1.0] * 3, abs=0.10)
    assert wavelength == pytest.approx(1.0, abs=0.004)
    assert all(n >= 2 for n in periods)


@pytest.mark.slow
def test_the_piston_makes_theorys_waves():
    """Issue 28, check 4, at dx = 0.02 m (H / dx = 2). Measured (2026-12-07, 549 s): heights
    0.9946, 0.9747, 0.9977 H at the three gauges, wavelength 1.0080. Bars: heights within
    7.5 % of H (3x the measured 2.5 %; was the issue's 10 %), wavelength within 2 % (the
    issue's; 3x the measured 0.8 % would be 2.4 %)."""
    heights, wavelength, periods = flume(0.02)
    print(f"heights {heights}, wavelength {wavelength}")
    assert heights == pytest.approx([1.0] * 3, abs=0.075)
    assert wavelength == pytest.approx(1.0, abs=0.02)
    assert all(n >= 2 for n in periods)
