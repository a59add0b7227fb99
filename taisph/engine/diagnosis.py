"""What went wrong when a guard trips, and what to do about it.

:func:`collect` reads the guard flags and the offending particles, :func:`explain`
turns them into a message (what, when, which particles and where, the likely cause
and a remedy), :func:`write_evidence` writes the last state that passed the guards
as a frame and the offending particles (in their failing state) as a separate .vtu,
both viewable in ParaView.
"""

from pathlib import Path

import numpy as np

from . import guards
from . import status as st
from .layout import FLUID
from ..scene.names import INTEGRATORS


class SimulationError(RuntimeError):
    """A guard tripped (non-finite state, density error, particle out of the domain).

    ``str(err)`` explains what happened, where, the likely cause and a remedy;
    ``err.report`` holds the same as data, ``err.files`` the frames written."""

    def __init__(self, message, report, files=()):
        super().__init__(message)
        self.report = report
        self.files = list(files)


def fail(sim, folder=None, stalled=False):
    """Collect, write the evidence (to `folder`, or a new temporary folder: a run with
    no output folder does not litter the working directory) and raise SimulationError.
    `stalled`: the host saw the clock stand still (``STALLED``, recorded here with the
    fastest fluid particles as the offending ones).

    The diagnosis outlives the evidence: if writing it fails (a full disk, a folder
    that cannot be written), the SimulationError says so and why, and lists only the files
    that were written."""
    import tempfile

    if stalled:
        speed = np.linalg.norm(sim.velocities(), axis=1)
        speed[~sim.fluid | ~np.isfinite(speed)] = -1.0
        guards.trip_from_host(sim.state, st.STALLED, np.argsort(speed)[::-1][:5])
    report = collect(sim)
    files, lost = [], None
    try:
        folder = Path(tempfile.mkdtemp(prefix=f"taisph-{sim.scene.name}-")) if folder is None else folder
        write_evidence(sim, report, folder, files)
    except Exception as err:  # noqa: BLE001 -- any failure here must not replace the diagnosis
        lost = err
    message = explain(sim, report, files)
    if lost is not None:
        where = f" to {folder}" if folder is not None else ""
        message += f"\nthe evidence could not be written{where}: {type(lost).__name__}: {lost}"
    raise SimulationError(message, report, files) from lost


def collect(sim) -> dict:
    state = sim.state
    flags = state.flags.to_numpy()
    status = state.status.to_numpy()
    count = int(flags[st.COUNT])
    records = guards.recorded(flags)
    vec, sca, ints = state.to_numpy()
    q = sim.solver.layout.q
    ids = records[:, 0]
    particles = []
    for pid, code in records:
        k = int(np.searchsorted(ints[q.id], pid))  # ids sorted; past the scene's for created particles
        particles.append(dict(
            id=int(pid),
            problems=[name for bit, name in st.CODE_NAMES.items() if code & bit],
            position=vec[q.position][k].tolist(),
            velocity=vec[q.velocity][k].tolist(),
            density=float(sca[q.density][k]),
        ))
    rho0 = np.array([getattr(m, "rho0", np.nan) for m in sim.scene.materials])
    fluid = ints[q.kind] == FLUID
    with np.errstate(invalid="ignore"):
        density_error = np.nanmax(np.abs(sca[q.density][fluid] / rho0[ints[q.material][fluid]] - 1.0), initial=0.0)
    return dict(
        codes=[name for bit, name in st.CODE_NAMES.items() if int(flags[st.CODES]) & bit],
        count=count,
        particles=particles,
        ids=ids,
        step=int(status[st.STEPS]),
        time=float(status[st.TIME]),
        dt=float(status[st.DT]),
        dt_fixed=sim.controls.dt,
        # the limit before things went wrong (a blow-up drives it to zero)
        dt_stable_min=float(state.good_dt_stable if state.has_good else status[st.DT_STABLE_MIN]),
        dt_stable=float(status[st.DT_STABLE]),
        last_good_time=state.good_time,
        last_good_step=state.good_steps,
        integrator=sim.scene.integrator,
        max_density_error=sim.controls.max_density_error,
        density_error=float(density_error),
        solver=getattr(sim.scene, "solver", "wcsph"),
        # a method that iterates a solve on the host: the solve that did not converge (Method.stepper)
        pressure_solve=dict(stepper.stats.failure) if (stepper := sim.pressure_solve) is not None else {},
    )


def likely_causes(sim, report) -> list:
    """The likely causes of what tripped, each with its remedy: the solver's method's
    account of a code where it gives one (:meth:`taisph.engine.method.Method.causes`),
    else the engine's, in the order below."""
    method = sim.solver.method

    def cause(code: str, default) -> list:
        if code not in report["codes"]:
            return []
        own = method.causes(code, sim, report)
        return own if own is not None else default(sim, report)

    causes = (cause(st.CODE_NAMES[st.UNCONVERGED], _none) + cause(st.CODE_NAMES[st.SPEED], _speed)
              + cause(st.CODE_NAMES[st.STALLED], _stalled) + cause(st.CODE_NAMES[st.CROWDED], _none)
              + _fixed_dt(sim, report) + _integrator(sim, report)
              + cause(st.CODE_NAMES[st.ESCAPED], _escaped) + cause(st.CODE_NAMES[st.DENSITY], _density))
    if not causes:
        causes = method.causes("diverged", sim, report)
    return causes or ["the state diverged; try a smaller dt (or the adaptive step) and the pc integrator"]


def _none(sim, report) -> list:
    return []


def _speed(sim, report) -> list:
    fastest = max((float(np.linalg.norm(p["velocity"])) for p in report["particles"]), default=float("nan"))
    limit = guards.max_speed(sim.scene, sim.controls, sim.solver.method.max_speed(sim.scene))
    return [f"a particle moved at {fastest:.3g} m/s, above max_speed = {limit:.3g} m/s: the flow blew up, "
            "or it is faster than the limit you set (--max-speed)"]


def _stalled(sim, report) -> list:
    return [f"the adaptive time step fell to zero (last stable limit {report['dt_stable']:.3g} s): a "
            "particle's speed or acceleration diverged (the fastest are listed); give a smaller maximum step "
            "(--dt-max) or CFL number (--courant)"]


def _fixed_dt(sim, report) -> list:
    fixed = report["dt_fixed"]
    if fixed is None or fixed <= report["dt_stable_min"]:
        return []
    return [f"dt {fixed:.3g} s is above the stability limit {report['dt_stable_min']:.3g} s "
            f"(CFL {sim.controls.courant} h/(c+|v|) and force {sim.controls.force_factor} sqrt(h/|a|)): "
            "use a smaller --dt, or none for the adaptive step"]


def _integrator(sim, report) -> list:
    if report["integrator"] not in INTEGRATORS or report["integrator"] == "pc":  # not the Euler family
        return []
    return [f"the {report['integrator']} integrator updates density with the old velocity, which lets "
            "the acoustic oscillation of weakly compressible SPH grow: use --integrator pc, or a much "
            "smaller dt"]


def _escaped(sim, report) -> list:
    advice = "".join(t.escape_advice + "; " for t in sim.scene.terms if t.escape_advice)  # (terms/base.py)
    return ["particles passed a wall or flew out of the domain: "
            + advice
            + "for an open domain, run with remove_escaped=True (--remove-escaped) to take them out and "
              "count them"]


def _density(sim, report) -> list:
    causes = []
    removed = sim.state.read_flag(st.OUT_OF_RANGE_COUNT)
    if removed:
        causes.append(f"{removed} particles whose density left the range were already removed (remove_escaped), "
                      f"the limit of max_out_of_range = {sim.controls.max_out_of_range:g} of the fluid "
                      "particles: more than a few particles in flight are out of range, the flow itself is")
    causes.append(f"density departs from rho0 by more than {report['max_density_error']:.0%}: the sound speed c0 is "
                  "too low for the flow speed (keep c0 >= 10 |v|max), or particles are being crushed against a "
                  "wall; raise c0 or --max-density-error")
    return causes


def explain(sim, report, files=()) -> str:
    who = (f"{report['count']} fluid particle(s) tripped the guards" if report["count"]
           else "a guard tripped")
    lines = [
        f"simulation stopped at step {report['step']}, t = {report['time']:.6g} s"
        + (f" (fixed dt = {report['dt_fixed']:.3g} s)" if report["dt_fixed"] else "")
        + f": {who} ("
        + ", ".join(report["codes"]) + ")"
        + f"; the last state that passed the guards is from step {report['last_good_step']}, "
        f"t = {report['last_good_time']:.6g} s."
    ]
    for p in report["particles"][:5]:
        pos = ", ".join(f"{x:.4g}" for x in p["position"])
        vel = ", ".join(f"{x:.4g}" for x in p["velocity"])
        lines.append(f"  particle {p['id']}: {', '.join(p['problems'])} at x = ({pos}), v = ({vel}), "
                     f"rho = {p['density']:.6g}")
    if report["count"] > 5:
        lines.append(f"  ... and {report['count'] - 5} more")
    lines.append("likely cause: " + "; ".join(likely_causes(sim, report)))
    if files:
        lines.append("written for ParaView: " + ", ".join(str(f) for f in files))
    return "\n".join(lines)


def write_evidence(sim, report, folder, files=None) -> list:
    """Write the evidence files to `folder`; return their paths, also appended to `files`
    as each is written (so a caller whose list it is knows what exists if one fails)."""
    from ..run.vtk import write_vtu

    files = [] if files is None else files
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    q = sim.solver.layout.q
    if sim.state.has_good:
        vec, sca, ints = sim.state.to_numpy(good=True)
        fluid = ints[q.kind] == FLUID
        path = folder / f"{sim.scene.name}_last_good.vtu"
        write_vtu(path, vec[q.position][fluid], _point_arrays(vec, sca, ints, q, fluid))
        files.append(path)
    vec, sca, ints = sim.state.to_numpy()
    bad = np.isin(ints[q.id], report["ids"])  # by id (created particles: ids past the scene's)
    if bad.any():
        path = folder / f"{sim.scene.name}_offending.vtu"
        write_vtu(path, np.nan_to_num(vec[q.position][bad], posinf=1e30, neginf=-1e30),
                  _point_arrays(vec, sca, ints, q, bad))
        files.append(path)
    return files


def _point_arrays(vec, sca, ints, q, select):
    return {
        "velocity": vec[q.velocity][select],
        "pressure": sca[q.pressure][select],
        "density": sca[q.density][select],
        "mass": sca[q.mass][select],
        "id": ints[q.id][select].astype(np.int32),
        "material": ints[q.material][select].astype(np.int32),
    }
