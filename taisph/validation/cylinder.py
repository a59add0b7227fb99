"""The drag on a cylinder in a channel against Schaefer & Turek's (1996) benchmark 2D-1
(Re 20; ``cases/cylinder.py``), for the work-precision study (issue 27), and the reading
of its force probe at Re 100 (2D-2: the Strouhal number and the maxima over a shedding
period), shared by tools/studies/cylinder_study.py and tests/test_cylinder.py.

The error is that of the drag coefficient C_D = 2 F_x / (rho U^2 D) (F_x the force
probe ``cylinder``, pressure and viscous, per metre; U the mean inflow speed) averaged
over the last ``WINDOW`` seconds of the run, against their 5.5795. The front-back
pressure difference (reference 0.1175 Pa) and the lift are reported beside it.
"""

from __future__ import annotations

import math

import numpy as np

from ..cases.cylinder import DIAMETER, NU, REFERENCE_RE20, RHO

# Schaefer & Turek's ranges for 2D-2 (Re 100): max C_D, max C_L over a period, St = f D / U
REFERENCE_RE100 = {"C_D_max": (3.22, 3.24), "C_L_max": (0.99, 1.01), "St": (0.295, 0.305)}
WINDOW = 2.0  # s: the means are over the run's last two seconds (the flow is steady after ~2 s)
ERROR_NAME = f"|C_D / {REFERENCE_RE20['C_D']} - 1| (mean of the last {WINDOW:g} s)"


def cylinder(run, params):
    """A validation run of the cylinder case (`run`: a :class:`taisph.validation.runs._Runner`
    of it with `params`, Re 20). Headline error: |C_D / 5.5795 - 1|; metrics: C_D, C_L, dp
    and their errors, the fluid mass's change."""
    from ..probes import Probes

    scene = run.scene
    re = params.get("re", 20.0)
    if re != 20.0:
        raise ValueError(f"the cylinder's validation is Schaefer & Turek's 2D-1 (re = 20), not re = {re:g}")
    probes = Probes(scene.probes, walls=scene.wall_groups)
    mass0 = float(run.sim.masses()[run.sim.fluid].sum())
    run.advance(scene.t_end, writers=[probes])
    if run.diverged:
        return run.outcome("cylinder", params, math.inf, ERROR_NAME, {}, {})
    c = coefficients(probe_table(probes), re)
    last = c["t"] > c["t"][-1] - WINDOW
    c_d, c_l, dp = (float(c[k][last].mean()) for k in ("C_D", "C_L", "dp"))
    metrics = {"C_D": c_d, "C_L": c_l, "dp": dp, "dp_rel_error": dp / REFERENCE_RE20["dp"] - 1.0,
               "C_D_rel_error": c_d / REFERENCE_RE20["C_D"] - 1.0,
               "mass_change": float(run.sim.masses()[run.sim.fluid].sum()) / mass0 - 1.0}
    every = max(1, len(c["t"]) // 2000)  # the series, thinned to ~2 000 samples
    series = {k: list(map(float, c[k][::every])) for k in ("t", "C_D", "dp")}
    return run.outcome("cylinder", params, abs(c_d / REFERENCE_RE20["C_D"] - 1.0), ERROR_NAME, metrics, series)


def probe_table(probes) -> dict:
    """The case's probes as the columns of its probes.csv (for :func:`coefficients`), from a
    :class:`taisph.probes.Probes` writer that took them in memory."""
    t, force = probes.series("cylinder")
    return {"time": t, "cylinder_x": force[:, 0], "cylinder_y": force[:, 1],
            "p_front": probes.series("p_front")[1], "p_back": probes.series("p_back")[1]}


def coefficients(table: dict, re: float) -> dict:
    """C_D(t), C_L(t) and dp(t) from a probes.csv table (:func:`taisph.probes.read_csv`)."""
    u_mean = re * NU / DIAMETER
    q = 0.5 * RHO * u_mean**2 * DIAMETER
    t = np.asarray(table["time"], float)
    keep = np.isfinite(np.asarray(table["cylinder_x"], float))
    return {"t": t[keep], "C_D": np.asarray(table["cylinder_x"], float)[keep] / q,
            "C_L": np.asarray(table["cylinder_y"], float)[keep] / q,
            "dp": (np.asarray(table["p_front"], float) - np.asarray(table["p_back"], float))[keep]}


def window_means(c: dict, average: float) -> dict:
    """Means over the last `average` seconds, and the change of C_D from the window before."""
    t_end = c["t"][-1]
    last = c["t"] > t_end - average
    before = (c["t"] > t_end - 2 * average) & ~last
    out = {k: float(np.mean(c[k][last])) for k in ("C_D", "C_L", "dp")}
    out["dC_D_window"] = float(out["C_D"] - np.mean(c["C_D"][before])) if before.any() else math.nan
    out["St"] = strouhal(c["t"][last], c["C_L"][last], out["C_L"])
    out["C_D_max"], out["C_L_max"] = (phase_max(c["t"][last], c[k][last], out["St"]) for k in ("C_D", "C_L"))
    return out


def phase_max(t, values, frequency: float, bins: int = 20) -> float:
    """The maximum over one shedding period of `values` averaged at equal phase: their
    0.02 s moving average over whole periods (1 / frequency) folded onto one and
    averaged in `bins` phase bins. The samples' acoustic noise (with the summed density
    larger than the shedding's swing) sets the maximum of any moving average alone;
    folding the ~6 periods of a 2 s window removes most of it. The estimate still depends
    on the filter's width and bins (docs/validation.md, "Re 100"). NaN without a
    frequency."""
    if not np.isfinite(frequency) or frequency <= 0:
        return math.nan
    smooth = moving_average(t, values, 0.02)
    cut = (len(t) - len(smooth)) // 2
    t, values = t[cut:cut + len(smooth)], smooth
    periods = math.floor((t[-1] - t[0]) * frequency)
    if periods < 1:
        return math.nan
    keep = t < t[0] + periods / frequency
    phase = ((t[keep] - t[0]) * frequency) % 1.0
    which = np.minimum((phase * bins).astype(int), bins - 1)
    means = np.bincount(which, weights=np.asarray(values, float)[keep], minlength=bins) / np.maximum(
        np.bincount(which, minlength=bins), 1)
    return float(means.max())


def moving_average(t, values, width: float):
    """The mean of `values` over each `width` seconds (centred; the samples are about
    evenly spaced): a low pass that keeps the shedding (a 0.02 s window lowers a 3 Hz
    oscillation's amplitude by 0.6 %) and removes most of the samples' acoustic noise."""
    if len(t) < 2:
        return np.asarray(values, float)
    n = max(1, int(round(width / np.median(np.diff(t)))))
    return np.convolve(values, np.ones(n) / n, mode="valid")


def strouhal(t, cl, mean) -> float:
    """The frequency f of C_L's oscillation (St = f D / U in main): the peak of the power
    spectrum of its 0.02 s moving average (the samples resampled evenly, the mean removed,
    zero-padded 8x), searched below 25 Hz (half the average's first zero; shedding at
    Re 100 is ~3 Hz). Without the low pass the samples' acoustic noise, far above the
    shedding's frequency with the summed density, holds the peak (docs/validation.md,
    "Re 100"). NaN below three periods or with no oscillation (peak-to-peak of a 0.05 s
    moving average below 0.05)."""
    if len(t) < 16:
        return math.nan
    even = np.linspace(t[0], t[-1], len(t))
    s = np.interp(even, t, cl) - mean
    step = even[1] - even[0]
    width = max(1, int(round(0.05 / step)))
    if np.ptp(np.convolve(s, np.ones(width) / width, mode="valid")) < 0.05:
        return math.nan
    s = moving_average(even, s, 0.02)
    power = np.abs(np.fft.rfft(s * np.hanning(len(s)), n=8 * len(s))) ** 2
    freq = np.fft.rfftfreq(8 * len(s), step)
    band = (freq > 0) & (freq < 25.0)
    k = int(np.flatnonzero(band)[np.argmax(power[band])])
    if freq[k] * (t[-1] - t[0]) < 3:
        return math.nan
    return float(freq[k])
