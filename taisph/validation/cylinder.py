"""The drag on a cylinder in a channel against Schaefer & Turek's (1996) benchmark 2D-1
(Re 20; ``cases/cylinder.py``), for the work-precision study (issue 27).

The error is that of the drag coefficient C_D = 2 F_x / (rho U^2 D) (F_x the force
probe ``cylinder``, pressure and viscous, per metre; U the mean inflow speed) averaged
over the last ``WINDOW`` seconds of the run, against their 5.5795. The front-back
pressure difference (reference 0.1175 Pa) and the lift are reported beside it.
"""

from __future__ import annotations

import math

from ..cases.cylinder import DIAMETER, NU, REFERENCE_RE20, RHO

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
    t, force = probes.series("cylinder")
    _, front = probes.series("p_front")
    _, back = probes.series("p_back")
    last = t > t[-1] - WINDOW
    q = 0.5 * RHO * (re * NU / DIAMETER) ** 2 * DIAMETER
    c_d, c_l = float(force[last, 0].mean() / q), float(force[last, 1].mean() / q)
    dp = float((front - back)[last].mean())
    metrics = {"C_D": c_d, "C_L": c_l, "dp": dp, "dp_rel_error": dp / REFERENCE_RE20["dp"] - 1.0,
               "C_D_rel_error": c_d / REFERENCE_RE20["C_D"] - 1.0,
               "mass_change": float(run.sim.masses()[run.sim.fluid].sum()) / mass0 - 1.0}
    every = max(1, len(t) // 2000)  # the series, thinned to ~2 000 samples
    series = {"t": list(map(float, t[::every])), "C_D": list(map(float, force[::every, 0] / q)),
              "dp": list(map(float, (front - back)[::every]))}
    return run.outcome("cylinder", params, abs(c_d / REFERENCE_RE20["C_D"] - 1.0), ERROR_NAME, metrics, series)
