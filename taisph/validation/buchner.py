"""The 2D dam break of Zhou, De Kat & Buchner (1999) against Buchner's (2002) wall
pressures: the scene file ``cases/dam_break_probes_2d.toml`` run with its probes.

A column of water H = 0.6 m high and 2H long collapses in a tank 3.22 m long; sensors
P1 (middle at y = 0.16 m) and P2 (0.584 m) on the right wall record the impact of the
surge and the run-up. Reference: the experimental curves in
``references/data/buchner2002_dambreak2d_pressure_P{1,2}.csv`` (sources in their
headers), in T = t sqrt(g/H) and P = p / (rho0 g H).

The scene file's probes ``P1`` and ``P2`` model the sensors as TrixiParticles.jl's
validation of this case does (validation/dam_break_2d/setup_marrone_2011.jl): the
pressure averaged over the sensor's face, 0.09 m tall, with its top at the middle of
the experimental sensor (P1: y in [0.07, 0.16] m), quoting Adami, Hu & Adams (2012,
J. Comput. Phys. 231:7057): the numerical probe does not exactly match the
experiment's position, "but Greco showed that this shift gives better agreement and
reported several uncertainties in the measurements". ``P1_point`` and ``P2_point``
are the pressure at the sensors' middles, for comparison (docs/validation.md).

Metrics (:func:`compare`), from the probe's samples (every step):

- ``impact_T``: the first T at which P reaches :data:`IMPACT_LEVEL` = 0.1 (linear
  interpolation between samples; experiment, P1: 2.479);
- ``mae``: the mean over the samples with T in [2, 6] of |P - P_exp(T)|, P_exp
  interpolated linearly between the experimental points (the sensor is dry before
  the surge: a probe that reads no value counts as P = 0, the pressure of the air);
- ``noise``: the rms over the samples from the impact to the window's end (where the
  average's window lies within the series) of P minus
  its moving average over 0.02 in T (:func:`moving_average`): the acoustic ringing and
  particle noise a smooth load would not have (issue 26's bar: 0.05 on P1);
- ``peak``, ``peak_ref``: the largest value of that moving average in the window, and
  of the experiment's (the first impact's peak on P1).

    >>> from taisph.validation import buchner
    >>> out = buchner.run(dx=0.01)              # doctest: +SKIP
    >>> out["P1"]["impact_T"], out["P1"]["mae"]  # doctest: +SKIP
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .outcome import Outcome
from .probed import run_probed
from ..scene.catalogue import find_scene_file
from ..terms import STANDARD_GRAVITY

DATA = Path(__file__).resolve().parent / "references" / "data"
H, G, RHO0 = 0.6, STANDARD_GRAVITY, 1000.0
IMPACT_LEVEL = 0.1  # P at which the impact is timed
WINDOW = (2.0, 6.0)  # T range of the mean absolute error
NOISE_WIDTH = 0.02  # T width of the moving average the probe noise is measured against (issue 26)
SENSORS = ("P1", "P2")
# the scene file's probes compared, and the sensor each one is compared with
PROBES = {"P1": "P1", "P2": "P2", "P1_point": "P1", "P2_point": "P2"}


def reference(sensor: str = "P1"):
    """(T, P) of Buchner's measurement at `sensor` ("P1" or "P2")."""
    path = DATA / f"buchner2002_dambreak2d_pressure_{sensor}.csv"
    data = np.loadtxt(path, delimiter=",", comments="#", skiprows=1 + sum(
        1 for line in path.read_text().splitlines() if line.startswith("#")))
    return data[:, 0], data[:, 1]


def scene_file() -> Path:
    return find_scene_file("dam_break_probes_2d.toml")


def impact_time(T, P, level: float = IMPACT_LEVEL) -> float:
    """The first T at which P reaches `level`, interpolated; NaN if it never does."""
    T, P = np.asarray(T, float), np.nan_to_num(np.asarray(P, float))
    above = np.flatnonzero(P >= level)
    if len(above) == 0:
        return math.nan
    k = above[0]
    if k == 0:
        return float(T[0])
    return float(T[k - 1] + (level - P[k - 1]) / (P[k] - P[k - 1]) * (T[k] - T[k - 1]))


def compare(T, P, sensor: str = "P1", window=WINDOW) -> dict:
    """Metrics of a simulated signal (T, P dimensionless; NaN = dry) against `sensor`."""
    T_ref, P_ref = reference(sensor)
    T, P = np.asarray(T, float), np.nan_to_num(np.asarray(P, float))
    inside = (T >= window[0]) & (T <= min(window[1], T_ref[-1]))
    mae = float(np.mean(np.abs(P[inside] - np.interp(T[inside], T_ref, P_ref)))) if inside.any() else math.nan
    impact, impact_ref = impact_time(T, P), impact_time(T_ref, P_ref)
    # after the impact, where the moving average's window is whole
    whole = (T - NOISE_WIDTH / 2 >= T[0]) & (T + NOISE_WIDTH / 2 <= T[-1]) if len(T) else inside
    wet = inside & whole & (T >= impact) if not math.isnan(impact) else np.zeros_like(inside)
    smooth = moving_average(T, P)
    noise = float(np.sqrt(np.mean((P[wet] - smooth[wet]) ** 2))) if wet.any() else math.nan
    peak = float(smooth[inside].max()) if inside.any() else math.nan
    return dict(impact_T=impact, impact_T_ref=impact_ref, impact_error=impact / impact_ref - 1.0, mae=mae,
                noise=noise, peak=peak, peak_ref=float(moving_average(T_ref, P_ref).max()),
                window=(float(window[0]), float(T[inside][-1]) if inside.any() else math.nan))


def moving_average(T, P, width: float = NOISE_WIDTH):
    """P averaged over [T - width/2, T + width/2] (samples at any spacing: the difference of
    P's running integral, trapezoidal, interpolated at the window's ends; the window is cut
    at the series' ends)."""
    T, P = np.asarray(T, float), np.nan_to_num(np.asarray(P, float))
    if len(T) < 2:
        return P.copy()
    integral = np.concatenate([[0.0], np.cumsum(0.5 * (P[1:] + P[:-1]) * np.diff(T))])
    lo, hi = np.maximum(T - width / 2, T[0]), np.minimum(T + width / 2, T[-1])
    span = hi - lo
    out = P.copy()
    ok = span > 0
    out[ok] = (np.interp(hi[ok], T, integral) - np.interp(lo[ok], T, integral)) / span[ok]
    return out


def run(dx: float = 0.01, t_end: float | None = None, out=None, overrides: dict | None = None, **controls) -> dict:
    """Run the scene file at `dx` to `t_end` (default: T = 6.1) with its probes, and
    compare its P1, P2 (and P1_point, P2_point) with the experiment. `overrides`:
    further scene-file keys (``{"physics.alpha": 0.05}``); `controls`: simulation
    controls (``max_density_error``, ``courant``...); `out`: a folder for probes.csv.
    Returns {"P1": metrics, ..., "P1_series": (T, P), ..., "dx", "steps", "wall_s",
    "setup_s", "fluid", "particles", "precision", "t_end", "stopped"} ("stopped": the first line of a guard's diagnosis,
    or "")."""
    scale = math.sqrt(G / H)
    t_end = 6.1 / scale if t_end is None else t_end
    series, result = run_probed(scene_file(), {"dx": dx, **(overrides or {})}, t_end, out, **controls)
    result["dx"] = dx
    for name, sensor in PROBES.items():
        if name in series:
            t, p = series[name]
            T, P = t * scale, p / (RHO0 * G * H)
            result[name] = compare(T, P, sensor)
            result[f"{name}_series"] = (T, P)
    return result


# --- the dam break's wall pressure -------------------------------------------------------------------------
def dam_break_pressure(precision=None, dx: float = 0.02, overrides: dict | None = None,
                       controls: dict | None = None) -> Outcome:
    """Buchner's (2002) wall pressure P1 in the 2D dam break of ``cases/dam_break_probes_2d.toml``
    (:mod:`taisph.validation.buchner`): headline the mean |P - P_exp| over T in [2, 6]
    (P = p / rho g H, T = t sqrt(g/H)), the measure of the dam break that converges with
    resolution (issue 26: the surge front against Koshizuka & Oka does not, the experiment's
    front being slower than the inviscid model's). `overrides`: scene-file keys changed
    (``{"physics.formulation": "symmetric"}``, ``{"solver": "dfsph"}``); `controls`:
    simulation controls (``{"courant": 0.5}``). Metrics: P1's noise, first peak and impact
    time error, P2's mean error."""
    controls = dict(controls or {})
    if precision is not None:
        controls["precision"] = precision
    out = run(dx=dx, overrides=overrides, **controls)
    p1, p2 = out["P1"], out.get("P2")
    stopped = bool(out["stopped"])
    metrics = dict(p1_noise=p1["noise"], p1_peak=p1["peak"], p1_peak_ref=p1["peak_ref"],
                   p1_impact_error=p1["impact_error"], p2_mae=p2["mae"] if p2 else math.nan, stopped=out["stopped"])
    params = dict(dx=dx, overrides=overrides or {}, controls=controls)
    return Outcome(case="dam_break_pressure", params=params, precision=out["precision"],
                   error=float("inf") if stopped else p1["mae"], error_name="P1: mean |P - P_Buchner|, T 2-6",
                   metrics=metrics, fluid=out["fluid"], particles=out["particles"], steps=out["steps"],
                   dt=out["t_end"] / max(out["steps"], 1), dx=dx, wall=out["wall_s"], setup=out["setup_s"],
                   sim_time=out["t_end"], series=dict(T=out["P1_series"][0].tolist(), P=out["P1_series"][1].tolist()),
                   diverged=stopped)
