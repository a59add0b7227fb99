"""Validation runs: each case against its reference, with its error and its cost.

Every function here builds a case (``taisph.cases``) with the given parameters, runs
it, compares it with its reference and returns an :class:`Outcome`: one headline
``error`` (the number the accuracy study plots), all the metrics computed on the way,
and the cost (steps, particles, wall seconds spent stepping, which excludes building
the simulation and compiling its kernels). The references are analytic
(:mod:`taisph.validation.references.analytic`) or experimental (CSV files in
``taisph/validation/references/data/`` with their sources in the headers). Tolerances and
measured values: ``docs/validation.md``.

    >>> from taisph import validation
    >>> out = validation.run("poiseuille", dx=5e-5)      # doctest: +SKIP
    >>> out.error, out.wall, out.steps                     # doctest: +SKIP

A run that blows up (non-finite state, or particles far outside the domain) stops at
the next sample and returns ``error = inf`` and ``diverged = True``. Besides the case's
parameters every function takes ``precision`` ("f32"/"f64") and ``dt_factor`` (the
case's time step is multiplied by it).
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .buchner import dam_break_pressure, scene_file
from .outcome import Outcome
from .references import analytic
from ..engine.timestep import fixed_dt
from ..run.simulation import Simulation
from ..scene import catalogue

DATA = Path(__file__).resolve().parent / "references" / "data"
# the dam break's front at dx = 0.005 (tools/studies/dam_break_reference.py)
FINE_FRONT = "dam_break_front_defaults_dx0.005.csv"


def reference(name: str) -> tuple[np.ndarray, str]:
    """An experimental data file of ``references/data`` as (columns array, header text)."""
    path = DATA / name
    header, rows = [], []
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            header.append(line[1:].strip())
        elif line.strip() and not line[0].isalpha():
            rows.append([float(v) for v in line.split(",")])
    return np.array(rows), "\n".join(header)


class _Runner:
    """Builds a simulation, runs it to sample times, accounts the stepping time.

    Besides the case's parameters, `params` may hold ``dt_factor`` (a fixed step of that
    many times the case's), ``controls`` (a dict of :class:`taisph.Simulation`
    controls, e.g. ``{"courant": 0.4}``) and ``solver`` ("wcsph" or "dfsph", the
    scene's ``solver``)."""

    def __init__(self, case, params, precision):
        params = dict(params)
        dt_factor = params.pop("dt_factor", 1.0)
        controls = params.pop("controls", None) or {}
        solver = params.pop("solver", None)
        self.scene = catalogue.find(case)(**params)
        if solver is not None:
            self.scene.solver = solver
        if dt_factor != 1.0:
            self.scene.dt = (self.scene.dt or fixed_dt(self.scene)) * dt_factor
        start = time.perf_counter()
        self.sim = Simulation(self.scene, precision=precision, **controls)
        self.setup = time.perf_counter() - start
        self.wall = 0.0
        self.diverged = False

    def advance(self, t: float, writers=()) -> bool:
        """Run to time t (with `writers`, e.g. probes); False (and diverged) if the state is
        no longer finite."""
        if self.diverged:
            return False
        if t > self.sim.time:
            self.wall += self.sim.run(t, frames=1, writers=writers).wall_time
        x, v = self.sim.positions(), self.sim.velocities()
        if not (np.isfinite(x).all() and np.isfinite(v).all() and np.isfinite(self.sim.density()).all()):
            self.diverged = True
            return False
        lo, hi = self.scene.domain
        span = np.max(hi - lo)
        if np.any(x < lo - span) or np.any(x > hi + span):
            self.diverged = True
            return False
        return True

    def outcome(self, case, params, error, name, metrics, series):
        sim = self.sim
        out = Outcome(case=case, params=dict(params), precision=sim.runtime.precision,
                      error=float("inf") if self.diverged else float(error), error_name=name,
                      metrics=metrics, fluid=sim.n_fluid, particles=sim.n, steps=sim.steps, dt=sim.dt,
                      dx=self.scene.dx, wall=self.wall, setup=self.setup, sim_time=sim.time, series=series,
                      diverged=self.diverged)
        sim.close()
        return out


def _deviations(name: str, d: np.ndarray) -> dict:
    """Mean and largest |d| and mean d over the points of `d`; NaN if it has none."""
    if not len(d):
        return {f"{name}_mean_abs": math.nan, f"{name}_max_abs": math.nan, f"{name}_mean_signed": math.nan}
    return {f"{name}_mean_abs": float(np.abs(d).mean()), f"{name}_max_abs": float(np.abs(d).max()),
            f"{name}_mean_signed": float(d.mean())}


# --- dam break ------------------------------------------------------------------------------------
def dam_break(precision=None, T_end: float = 3.1, samples: int = 32, against: str = "koshizuka_oka",
              **params) -> Outcome:
    """Surge front Z = x_front/L against T = t sqrt(2 g/L) (Koshizuka & Oka 1996 as
    shipped by PySPH; Martin & Moyce 1952 table, n^2 = 2) and residual column height
    H = h/(2L) against tau = t sqrt(g/L) (Martin & Moyce), for T <= T_end.

    x_front is the largest fluid x plus dx/2 (a particle stands for a dx-wide cell,
    so Z = 1 at t = 0); h is the highest fluid y (plus dx/2) within 0.1 L of the back
    wall. Headline error: mean |Z - Z_KO| over the Koshizuka & Oka points.

    Each error is computed over the reference points that exist up to T_end: with a
    small T_end a reference may have none (Martin & Moyce's front starts at T = 0.41,
    their column height at tau = 0.56, i.e. T = 0.79), and its metrics are then NaN
    (Koshizuka & Oka's first point is T = 0, so the headline error always exists).

    ``against="fine"`` (the study's case "dam_break_front", issue 26): the headline is
    mean |Z - Z_fine| over the `samples` even times (plus the references') up to T_end,
    Z_fine the same model's front at dx = 0.005 (FINE_FRONT, made by
    ``python -m tools.studies.dam_break_reference``), linear between its points: an error
    that falls as the resolution rises, which the experiments' does not (docs/accuracy.md)."""
    ko, _ = reference("koshizuka_oka_1996_surge_front_pysph.csv")
    mm, _ = reference("martin_moyce_1952_surge_front_table.csv")
    hh, _ = reference("martin_moyce_1952_column_height_table.csv")
    run = _Runner("dam_break", params, precision)
    sc = run.scene
    g = -sc.terms_by_name["gravity"].values["gravity"][1]
    L = float(sc.position[sc.kind == 0, 0].max() + sc.dx / 2)  # column width
    dx = sc.dx
    scale_T = math.sqrt(2 * g / L)
    ko = ko[ko[:, 0] <= T_end + 1e-9]
    mm = mm[mm[:, 0] <= T_end + 1e-9]
    hh = hh[hh[:, 0] <= T_end / math.sqrt(2) + 1e-9]
    times = sorted({*(ko[:, 0] / scale_T), *(mm[:, 0] / scale_T), *(hh[:, 0] / math.sqrt(g / L)),
                    *np.linspace(0, T_end / scale_T, samples)})
    front, height = {}, {}
    for t in times:
        if not run.advance(t):
            break
        x = run.sim.positions()[run.sim.fluid]
        front[round(t, 12)] = (x[:, 0].max() + dx / 2) / L
        near = x[:, 0] < 0.1 * L
        height[round(t, 12)] = (x[near, 1].max() + dx / 2) / (2 * L) if near.any() else 0.0
    metrics, series = {}, {}
    error = float("inf")
    if not run.diverged:
        z = lambda T: front[round(T / scale_T, 12)]  # noqa: E731
        d_ko = np.array([z(T) for T in ko[:, 0]]) - ko[:, 1]
        d_mm = np.array([z(T) for T in mm[:, 0]]) - mm[:, 1]
        d_h = np.array([height[round(tau / math.sqrt(g / L), 12)] for tau in hh[:, 0]]) - hh[:, 1]
        metrics = {**_deviations("ko", d_ko), **_deviations("mm", d_mm), **_deviations("height", d_h)}
        del metrics["height_mean_signed"]
        ts = np.array(sorted(front))
        series = dict(T=(ts * scale_T).tolist(), Z=[front[round(t, 12)] for t in ts],
                      tau=(ts * math.sqrt(g / L)).tolist(), H=[height[round(t, 12)] for t in ts])
        if (DATA / FINE_FRONT).exists() or against == "fine":
            fine = reference(FINE_FRONT)[0]
            d_fine = np.array(series["Z"]) - np.interp(series["T"], fine[:, 0], fine[:, 1])
            metrics.update(_deviations("fine", d_fine[np.array(series["T"]) <= fine[-1, 0] + 1e-9]))
        error = metrics["fine_mean_abs" if against == "fine" else "ko_mean_abs"]
    if against == "fine":
        return run.outcome("dam_break_front", params, error, "mean |Z - Z_fine|, T <= %g (Z_fine: the defaults at "
                           "dx = 0.005)" % T_end, metrics, series)
    return run.outcome("dam_break", params, error, "mean |Z - Z_KO|, T <= %g" % T_end, metrics, series)


# --- hydrostatic tank ---------------------------------------------------------------------------------
def hydrostatic_tank(precision=None, t_end: float | None = None, samples: int = 20, **params) -> Outcome:
    """Still water: rms(p - rho0 g (H - y)) / (rho0 g H) over the fluid deeper than one
    kernel support (the SPH pressure is not expected to match within a kernel radius
    of the free surface), max |v| / sqrt(g H), flatness of the surface (standard
    deviation of the top particle row's y over dx) and wall penetration (fluid
    particles outside the tank). Headline: the rms pressure error averaged over the
    samples of the second half of the run (Lennard-Jones walls keep an acoustic
    oscillation, so one instant would be arbitrary)."""
    run = _Runner("hydrostatic_tank", params, precision)
    sc = run.scene
    t_end = sc.t_end if t_end is None else t_end
    g = -sc.terms_by_name["gravity"].values["gravity"][1]
    rho0 = sc.materials[0].rho0
    fluid0 = sc.position[sc.kind == 0]
    H = float(fluid0[:, 1].max() + sc.dx / 2)
    W = float(fluid0[:, 0].max() + sc.dx / 2)
    top0 = fluid0[:, 1] > H - sc.dx
    ts, rms, vmax, flat, outside = [], [], [], [], []
    for k in range(1, samples + 1):
        t = t_end * k / samples
        if not run.advance(t):
            break
        x = run.sim.positions()[run.sim.fluid]
        p = run.sim.pressure()[run.sim.fluid]
        v = run.sim.velocities()[run.sim.fluid]
        deep = x[:, 1] < H - sc.support_radius
        ts.append(t)
        rms.append(float(np.sqrt(np.mean((p[deep] - rho0 * g * (H - x[deep, 1])) ** 2)) / (rho0 * g * H)))
        vmax.append(float(np.abs(v).max() / math.sqrt(g * H)))
        flat.append(float(x[top0, 1].std() / sc.dx))
        outside.append(int(np.count_nonzero((x[:, 0] < 0) | (x[:, 0] > W) | (x[:, 1] < 0))))
    error = float("inf")
    metrics = {}
    if not run.diverged:
        half = [r for t, r in zip(ts, rms) if t > t_end / 2 + 1e-12]
        error = float(np.mean(half))
        n4 = max(1, len(vmax) // 4)
        metrics = dict(rms_mean_second_half=error, rms_end=rms[-1], vmax_first_quarter=float(np.max(vmax[:n4])),
                       vmax_last_quarter=float(np.max(vmax[-n4:])), surface_std_over_dx=float(np.max(flat)),
                       particles_outside=int(np.max(outside)), t_end=t_end)
    return run.outcome("hydrostatic_tank", params, error, "rms (p - rho g (H-y)) / rho g H", metrics,
                       dict(t=ts, rms=rms, vmax=vmax, surface_std=flat))


# --- channel flows ------------------------------------------------------------------------------------------
CHANNEL_TIMES = (0.0225, 0.045, 0.1125, 0.225, 1.0)


def _channel(case, precision, times, params):
    run = _Runner(case, params, precision)
    sc = run.scene
    nu = sc.terms_by_name["laminar_viscosity"].values["nu"]
    L = float(sc.position[sc.kind == 0, 1].max() + sc.dx / 2)
    if case == "poiseuille":
        F = sc.terms_by_name["gravity"].values["gravity"][0]
        u_ref = F * L * L / (8 * nu)
        exact = lambda y, t: analytic.poiseuille_startup(y, t, L, nu, F)  # noqa: E731
    else:
        V0 = float(sc.velocity[sc.kind == 1, 0].max())
        u_ref = V0
        exact = lambda y, t: analytic.couette_startup(y, t, L, nu, V0)  # noqa: E731
    linf, l2, ts, profiles = [], [], [], []
    for t in times:
        if not run.advance(t):
            break
        x = run.sim.positions()[run.sim.fluid]
        u = run.sim.velocities()[run.sim.fluid]
        err = u[:, 0] - exact(x[:, 1], t)
        ts.append(t)
        linf.append(float(np.abs(err).max() / u_ref))
        l2.append(float(np.sqrt(np.mean(err**2)) / u_ref))
        order = np.argsort(x[:, 1])
        profiles.append(dict(y=(x[order, 1] / L).tolist(), u=(u[order, 0] / u_ref).tolist()))
    error = float("inf") if run.diverged else max(linf)
    metrics = {} if run.diverged else dict(linf_max=max(linf), l2_max=max(l2),
                                          **{f"linf_t{t:g}": e for t, e in zip(ts, linf)})
    return run.outcome(case, params, error, "max over t of max |u - u_exact| / u_max", metrics,
                       dict(t=ts, linf=linf, l2=l2, profiles=profiles))


def poiseuille(precision=None, times=CHANNEL_TIMES, **params) -> Outcome:
    """Start-up Poiseuille flow against the series solution of Morris et al. (1997):
    max |u - u_exact| / u_max (u_max = F L^2/(8 nu)) over all particles at t = 0.0225,
    0.045, 0.1125, 0.225 and 1 s (the last one steady); headline: the largest."""
    return _channel("poiseuille", precision, times, params)


def couette(precision=None, times=CHANNEL_TIMES, **params) -> Outcome:
    """Start-up Couette flow against the series solution of Morris et al. (1997):
    max |u - u_exact| / V0 at t = 0.0225, 0.045, 0.1125, 0.225 and 1 s; headline: the
    largest (the first time, when the profile is steepest)."""
    return _channel("couette", precision, times, params)


# --- Taylor-Green -------------------------------------------------------------------------------------------
def taylor_green(precision=None, t_end: float = 2.0, samples: int = 8, **params) -> Outcome:
    """Taylor-Green vortex against the exact decaying solution. PySPH's metric: the L1
    error of the speed, mean |(|v| - |v_exact|)| / mean |v_exact| (particles at their
    own positions); also the L1 error of the velocity vector, the error of max |v|
    against U exp(-8 pi^2 nu t/L^2) and the kinetic energy ratio. Headline: the L1
    speed error at t_end (2 s: PySPH's EDAC reaches 0.020 there with 50 x 50)."""
    run = _Runner("taylor_green", params, precision)
    sc = run.scene
    nu = sc.terms_by_name["laminar_viscosity"].values["nu"]
    U = float(np.abs(sc.velocity).max())
    L = float(sc.domain[1][0] - sc.domain[0][0])
    rho0 = sc.materials[0].rho0
    ts, l1, l1v, dmax, ke = [], [], [], [], []
    for k in range(1, samples + 1):
        t = t_end * k / samples
        if not run.advance(t):
            break
        x, v = run.sim.positions(), run.sim.velocities()
        ue, ve, _ = analytic.taylor_green(x[:, 0], x[:, 1], t, U=U, L=L, nu=nu, rho=rho0)
        speed, speed_e = np.hypot(v[:, 0], v[:, 1]), np.hypot(ue, ve)
        ts.append(t)
        l1.append(float(np.mean(np.abs(speed - speed_e)) / np.mean(speed_e)))
        l1v.append(float(np.mean(np.hypot(v[:, 0] - ue, v[:, 1] - ve)) / np.mean(speed_e)))
        decay = U * math.exp(-8 * math.pi**2 * nu * t / L**2)
        dmax.append(float(abs(speed.max() - decay) / decay))
        ke.append(float(np.sum(speed**2) / np.sum(speed_e**2)))
    error = float("inf") if run.diverged else l1[-1]
    metrics = {} if run.diverged else dict(l1_end=l1[-1], l1_vector_end=l1v[-1], max_speed_error_end=dmax[-1],
                                          kinetic_energy_ratio_end=ke[-1], l1_max=max(l1))
    return run.outcome("taylor_green", params, error, f"L1 speed error at t = {t_end:g}", metrics,
                       dict(t=ts, l1=l1, l1_vector=l1v, max_speed_error=dmax, kinetic_energy_ratio=ke))


# --- elliptical drop -----------------------------------------------------------------------------------------
def elliptical_drop(precision=None, samples: int = 4, **params) -> Outcome:
    """Semi-major axis against the ODE solution b(t) (``analytic.elliptical_drop``):
    b_sim = R max|y|(t) / max|y|(0), the cloud's extent along y scaled by its initial
    extent (the outermost particles sit about dx/2 inside the circle of radius R, and
    the exact motion maps y to y b/R). Also b from the second moment,
    R sqrt(<y^2>(t) / <y^2>(0)) (the whole drop, not only its tip), and the same for a.
    Headline: |b_sim - b| / b at t_end."""
    run = _Runner("elliptical_drop", params, precision)
    sc = run.scene
    R = params.get("R", 1.0)
    A0 = params.get("A0", 100.0)
    x0 = sc.position
    ymax0, y20, x20 = np.abs(x0[:, 1]).max(), np.mean(x0[:, 1] ** 2), np.mean(x0[:, 0] ** 2)
    ts, eb, ebm, eam = [], [], [], []
    for k in range(1, samples + 1):
        t = sc.t_end * k / samples
        if not run.advance(t):
            break
        x = run.sim.positions()
        a, b, _ = analytic.elliptical_drop(t, R=R, A0=A0)
        ts.append(t)
        eb.append(float((R * np.abs(x[:, 1]).max() / ymax0 - b) / b))
        ebm.append(float((R * math.sqrt(np.mean(x[:, 1] ** 2) / y20) - b) / b))
        eam.append(float((R * math.sqrt(np.mean(x[:, 0] ** 2) / x20) - a) / a))
    error = float("inf") if run.diverged else abs(eb[-1])
    metrics = {} if run.diverged else dict(b_rel_error_end=eb[-1], b_moment_rel_error_end=ebm[-1],
                                          a_moment_rel_error_end=eam[-1])
    return run.outcome("elliptical_drop", params, error, "|b - b_exact| / b_exact at t_end", metrics,
                       dict(t=ts, b_error=eb, b_moment_error=ebm, a_moment_error=eam))


def scene_of(case: str, params: dict):
    """The scene a validation run of `case` with `params` steps, for a sweep worker to
    compile before it is timed; None for the cases built by their factory (``catalogue``)."""
    if case != "dam_break_pressure":
        return None
    from ..formats.scenefile import load

    overrides = params.get("overrides") or {}
    return load(scene_file(), {"dx": params.get("dx", 0.02), **overrides})[0]


def wave_flume(precision=None, **params) -> Outcome:
    """The piston wave maker's regular waves against first-order theory
    (:func:`taisph.validation.waves.wave_flume`)."""
    from .waves import wave_flume as validate

    return validate(_Runner("wave_flume", params, precision), params)


def cylinder(precision=None, **params) -> Outcome:
    """Schaefer & Turek's cylinder at Re 20: its drag against theirs
    (:func:`taisph.validation.cylinder.cylinder`)."""
    from .cylinder import cylinder as validate

    return validate(_Runner("cylinder", params, precision), params)


SCENE_CASES = {"dam_break_front": "dam_break"}  # validations that step another case's scene
VALIDATIONS = {
    "dam_break": dam_break,
    "dam_break_front": lambda precision=None, **params: dam_break(precision, against="fine", **params),
    "dam_break_pressure": dam_break_pressure,
    "hydrostatic_tank": hydrostatic_tank,
    "poiseuille": poiseuille,
    "couette": couette,
    "taylor_green": taylor_green,
    "elliptical_drop": elliptical_drop,
    "wave_flume": wave_flume,
    "cylinder": cylinder,
}


def run(case: str, precision: str | None = None, **params) -> Outcome:
    """Run the validation of `case` with case parameters `params` (e.g. dx=...)."""
    try:
        func = VALIDATIONS[case]
    except KeyError:
        raise ValueError(f"no validation for {case!r}; have: {', '.join(VALIDATIONS)}") from None
    return func(precision=precision, **params)
