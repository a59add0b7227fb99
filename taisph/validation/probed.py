"""A scene file run with its probes, for the validations against experiments that read
probes (:mod:`taisph.validation.buchner`, :mod:`taisph.validation.kleefsman`)."""

from __future__ import annotations

import time
from pathlib import Path

from ..formats.scenefile import load
from ..probes import Probes
from ..run.simulation import Simulation, SimulationError


def run_probed(path, overrides: dict, t_end: float, out=None, **controls) -> tuple[dict, dict]:
    """Run the scene file `path` with `overrides` (scene-file keys) to `t_end` with its
    probes (into `out`/probes.csv if `out`), the file's Courant number unless `controls`
    give one. Returns ``(series, run)``: {probe name: (times, values)} of every probe,
    and {"steps", "wall_s" (stepping), "setup_s" (building the simulation), "fluid",
    "particles", "precision", "t_end", "stopped"} ("stopped": the first line of a guard's
    diagnosis, or "")."""
    scene, settings = load(path, {"t_end": t_end, **overrides})
    if settings.courant is not None:
        controls.setdefault("courant", settings.courant)
    start = time.perf_counter()
    sim = Simulation(scene, **controls)
    setup = time.perf_counter() - start
    probes = Probes(settings.probes, walls=settings.wall_groups,
                    path=Path(out) / "probes.csv" if out is not None else None)
    stopped = ""
    start = time.perf_counter()
    try:
        sim.run(t_end, frames=1, writers=[probes])
    except SimulationError as err:
        stopped = str(err).splitlines()[0]
    wall = time.perf_counter() - start
    series = {p.name: probes.series(p.name) for p in settings.probes}
    run = dict(steps=sim.steps, wall_s=wall, setup_s=setup, fluid=scene.n_fluid, particles=sim.n,
               precision=sim.runtime.precision, t_end=sim.time, stopped=stopped)
    probes.close()
    sim.close()
    return series, run
