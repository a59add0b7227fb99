"""DFSPH's account of a failed run (:meth:`taisph.engine.method.Method.causes`): the
causes and remedies of what its solves and its guards see, in the terms of its
controls (``--dfsph-max-iterations``, ``--dfsph-tolerance``...); the engine's
diagnosis (:mod:`taisph.engine.diagnosis`) says everything else."""

import numpy as np

from .. import guards
from .. import status as st


def causes(code: str, sim, report) -> list | None:
    """Its causes of the guard `code` (a name of ``status.CODE_NAMES``, or "diverged"),
    or None for the engine's."""
    explain = _CAUSES.get(code)
    return None if explain is None else explain(sim, report)


def _unconverged(sim, report) -> list:
    """A solve ended beyond its bound (``Stats.failure``), after its retries."""
    failure = report.get("pressure_solve") or {}
    if not failure:
        return []
    c, f = sim.controls, failure
    dt_max, courant, force, iterations = (f"{0.5 * f['dt']:.2g}", f"{0.5 * c.courant:.2g}",
                                          f"{0.5 * c.force_factor:.2g}", 2 * f["iterations"])
    return [
        f"the {f['solve']} solve reached {f['iterations']} iterations with a mean density error of "
        f"{100 * f['error']:.3g} % (tolerance {100 * f['tolerance']:.3g} %, kept up to {f['bound']:g} times that) "
        f"at dt = {f['dt']:.3g} s" + (f" (after {f['retries']} retries of the step, each with half the dt)"
                                       if f.get("retries") else "")
        + ": the step was too large for the solve; give a smaller maximum step "
        f"(--dt-max {dt_max}), a smaller CFL number (--courant {courant}, now {c.courant:g}) or force factor "
        f"(--force-factor {force}, now {c.force_factor:g}), or allow more iterations (--dfsph-max-iterations "
        f"{iterations}, now {f['iterations']}); in Python Simulation(scene, dt_max={dt_max}, courant={courant}, "
        f"force_factor={force}, dfsph_max_iterations={iterations})"]


def _speed(sim, report) -> list:
    fastest = max((float(np.linalg.norm(p["velocity"])) for p in report["particles"]), default=float("nan"))
    limit = guards.max_speed(sim.scene, sim.controls, sim.solver.method.max_speed(sim.scene))
    return [
        f"a particle moved at {fastest:.3g} m/s, above max_speed = {limit:.3g} m/s (by default the sound speed "
        "c0, 10 times the flow's speed in the cases): the pressure solve kicked it; give a smaller maximum step "
        f"(--dt-max) or CFL number (--courant, now {sim.controls.courant:g}), or a tighter --dfsph-tolerance "
        f"(now {sim.controls.dfsph_tolerance:g}); if the flow is really that fast, raise --max-speed "
        "(in Python Simulation(scene, max_speed=...))"]


def _crowded(sim, report) -> list:
    return ["a particle had more neighbours than DFSPH's pair list holds (taisph.engine.dfsph.pairs): particles "
            "were crushed together, or the walls are sampled more finely than dx (DFSPH needs wall particles "
            "dx apart, e.g. dummy-wall layers)"]


def _density(sim, report) -> list:
    return [f"the density exceeds rho0 by more than {report['max_density_error']:.0%}: the pressure solve "
            "lets particles be crushed; lower --dfsph-tolerance or the maximum step (--dt-max)"]


def _diverged(sim, report) -> list:
    return ["the state diverged; try a smaller maximum step (--dt-max) or CFL number (--courant)"]


_CAUSES = {st.CODE_NAMES[st.UNCONVERGED]: _unconverged, st.CODE_NAMES[st.SPEED]: _speed,
           st.CODE_NAMES[st.CROWDED]: _crowded, st.CODE_NAMES[st.DENSITY]: _density, "diverged": _diverged}
