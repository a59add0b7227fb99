"""Regular waves measured at wave gauges, for the piston wave maker's validation
(issue 28, check 4; ``cases/wave_flume.py``).

A gauge's record eta(t) (free-surface height) is read over a window of whole periods
that starts when the ramped-up wave train's full part has reached the gauge and ends
before anything reflected from the far end does:

    start = ramp T + x / c_g + T,   end = (2 L - x) / c   (or t_end with an absorber),

c = L_w / T the phase speed and c_g = c (1 + 2kh / sinh 2kh) / 2 the group speed of
first-order theory (Dean & Dalrymple 1991, ch. 4), x the gauge's distance from the
piston and L the flume's length. Over the window:

- **wave height**: the mean over the window's whole periods of max(eta) - min(eta) in
  each period (zero-crossing analysis, as a gauge in a flume is read);
- **phase**: the least-squares fit eta = a cos(omega t) + b sin(omega t) + c; for a
  progressive wave eta = A cos(kx - omega t), a = A cos kx and b = A sin kx, so the phase
  atan2(b, a) grows along the flume as k x;
- **wavelength**: 2 pi over the slope of the gauges' phases against x (a least-squares
  line through two or more gauges; phases unwrapped about theory's k x, so that gauges
  more than half a wavelength apart are read right), against the dispersion relation
  omega^2 = g k tanh kh.
"""

from __future__ import annotations

import math

import numpy as np

from ..cases.wave_flume import GAUGES, expected
from ..scene import wave_makers


def window(x, period, depth, ramp, length, t_end, absorber=False, g=wave_makers.G) -> tuple[float, float]:
    """(start, end) of the whole periods to read at a gauge `x` m from the piston (module
    docstring); end <= start if no whole period fits."""
    th = expected(depth, 1.0, period, g)
    start = ramp * period + x / th["group"] + period
    end = t_end if absorber else min(t_end, (2 * length - x) / th["celerity"])
    whole = math.floor((end - start) / period)
    return start, start + whole * period


def _within(t, eta, start, end):
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    keep = (t >= start) & (t <= end) & np.isfinite(eta)
    return t[keep], eta[keep]


def wave_height(t, eta, start, end, period) -> float:
    """Mean crest-to-trough height over the whole periods in [start, end] (NaN if none)."""
    heights = []
    for k in range(int(round((end - start) / period))):
        _, e = _within(t, eta, start + k * period, start + (k + 1) * period)
        if len(e) > 3:
            heights.append(e.max() - e.min())
    return float(np.mean(heights)) if heights else math.nan


def phase(t, eta, start, end, period) -> tuple[float, float]:
    """(amplitude, phase) of the least-squares fit a cos wt + b sin wt + c over [start, end]."""
    t, e = _within(t, eta, start, end)
    w = 2 * math.pi / period
    basis = np.column_stack([np.cos(w * t), np.sin(w * t), np.ones_like(t)])
    (a, b, _), *_ = np.linalg.lstsq(basis, e, rcond=None)
    return float(math.hypot(a, b)), float(math.atan2(b, a))


def wavelength(xs, phases, k_guess=0.0) -> float:
    """2 pi / slope of the gauges' phases against x, unwrapped in the order of x about
    `k_guess` x (theory's wavenumber: gauges farther apart than half a wavelength are
    then read right as long as the wave's k is within pi / spacing of the guess)."""
    order = np.argsort(xs)
    x = np.asarray(xs, float)[order]
    p = np.unwrap(np.asarray(phases, float)[order] - k_guess * x) + k_guess * x
    slope = np.polyfit(x, p, 1)[0]
    return float(2 * math.pi / abs(slope))


def measure(times, gauges: dict, xs, *, height, period, depth, ramp, length, t_end, absorber=False,
            g=wave_makers.G) -> dict:
    """Every gauge's height over the target H and windows, and the wavelength over
    theory's, from {name: eta(t)} at distances `xs` (m, in the same order) from the
    piston. Returns {"heights": [H_meas / H], "windows": [(start, end)], "periods": [n],
    "wavelength": L_meas / L_theory, "wavelength_m": L_meas, "theory": expected(...)}."""
    th = expected(depth, height, period, g)
    heights, windows, phases, periods = [], [], [], []
    for (name, eta), x in zip(gauges.items(), xs):
        start, end = window(x, period, depth, ramp, length, t_end, absorber, g)
        if end <= start:
            raise ValueError(f"gauge {name} at x = {x:g} m: no whole period between the wave train's arrival "
                             f"({start:.3g} s) and the end of the record or the reflection ({end:.3g} s)")
        windows.append((start, end))
        periods.append(int(round((end - start) / period)))
        heights.append(wave_height(times, eta, start, end, period) / height)
        phases.append(phase(times, eta, start, end, period)[1])
    measured = wavelength(xs, phases, th["k"])
    return dict(heights=heights, windows=windows, periods=periods, wavelength=measured / th["wavelength"],
                wavelength_m=measured, theory=th)


ERROR_NAME = "max |H / H_theory - 1| over the gauges"


def wave_flume(run, params):
    """A validation run of ``cases/wave_flume.py`` (`run`: a
    :class:`taisph.validation.runs._Runner` of it with `params`): its gauges g1-g3 read
    over their windows (:func:`measure`). Headline error: the largest |H_meas / H - 1| over
    the gauges; metrics: each gauge's H_meas / H, the wavelength over theory's, the periods
    read."""
    from ..probes import Probes

    scene = run.scene
    gauges = Probes([q for q in scene.probes if q.kind == "elevation"])
    names = [f"g{k + 1}" for k in range(len(GAUGES))]
    run.advance(scene.t_end, writers=[gauges])
    get = _defaults(params)
    if run.diverged:
        return run.outcome("wave_flume", params, math.inf, ERROR_NAME, {}, {})
    result = measure(np.asarray(gauges.times), {n: np.asarray(gauges.values[n]) for n in names}, GAUGES,
                     height=get("height"), period=get("period"), depth=get("depth"), ramp=get("ramp"),
                     length=get("length"), t_end=scene.t_end, absorber=bool(get("absorber")), g=get("g"))
    error = max(abs(h - 1.0) for h in result["heights"])
    metrics = {**{f"{n}_height": h for n, h in zip(names, result["heights"])},
               "wavelength": result["wavelength"], "periods": result["periods"]}
    series = {"t": list(map(float, gauges.times)), **{n: list(map(float, gauges.values[n])) for n in names}}
    return run.outcome("wave_flume", params, error, ERROR_NAME, metrics, series)


def _defaults(params):
    """`params`' value of a wave_flume parameter, or its default."""
    import inspect

    from ..cases.wave_flume import wave_flume as case

    signature = inspect.signature(case)
    return lambda name: params.get(name, signature.parameters[name].default)
