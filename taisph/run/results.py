"""A run's headline results: the quantity a case exists to measure (the cylinder's drag
coefficient, the wave flume's wave height, the floating box's draft...), computed when
the run ends, printed and written to ``OUT/results.json`` (docs/results.md).

A case declares them as a plug-in: its module (``cases/<name>.py``) defines

    def headline(sim, out) -> list[Result]

which reads the finished simulation `sim` (its state, ``sim.scene.case_parameters``,
``sim.bodies()``...) and, where a quantity is a mean over the run, the run's
``OUT/probes.csv`` (`out` the output folder, or None); :func:`probe_table` and
:func:`sample_probes` help. A headline only reads: it never steps, sets or writes
the simulation, so reporting never changes a trajectory. :func:`report` finds the
function through the case that made the scene (``scene.case``, set by the case's
``@checked``; :func:`taisph.scene.catalogue.case_module`), so a scene named otherwise
still finds its case; a scene not made by a case (a scene file, a scene built in
Python) has no headline: :func:`report` returns [] and writes nothing.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .atomic import write_text

RESULTS_FILE = "results.json"
DIMENSIONLESS = "1"  # the unit of a ratio or coefficient (as UDUNITS writes it)


@dataclass(frozen=True)
class Result:
    """One headline quantity: `value` in `unit` (``"1"``: dimensionless; NaN where it
    could not be measured, `note` then says why), the `reference` value it is measured
    against and the reference's `source` (None and "" without one), and `note`: how it
    was measured (e.g. "mean over t in [6, 8] s")."""

    name: str
    value: float
    unit: str = DIMENSIONLESS
    reference: float | None = None
    source: str = ""
    note: str = ""

    @property
    def relative_error(self) -> float | None:
        """value / reference - 1, or None without a (nonzero, finite) reference or value."""
        if self.reference is None or not math.isfinite(self.reference) or self.reference == 0:
            return None
        if not math.isfinite(self.value):
            return None
        return self.value / self.reference - 1.0

    def line(self) -> str:
        """The result as one printable line, e.g. ``C_D = 5.69 (reference 5.5795, Schaefer &
        Turek (1996): +2.0 %; mean over t in [6, 8] s)``."""
        unit = "" if self.unit in ("", DIMENSIONLESS) else f" {self.unit}"
        value = f"{self.value:.4g}{unit}" if math.isfinite(self.value) else "not measured"
        parts = []
        if self.reference is not None:
            error = self.relative_error
            source = f", {self.source}" if self.source else ""
            parts.append(f"reference {self.reference:.5g}{unit}{source}"
                         + (f": {100 * error:+.1f} %" if error is not None else ""))
        if self.note:
            parts.append(self.note)
        return f"{self.name} = {value}" + (f" ({'; '.join(parts)})" if parts else "")

    def as_dict(self) -> dict:
        """The result's entry in results.json (non-finite numbers as null)."""
        return {"value": _finite(self.value), "unit": self.unit, "reference": _finite(self.reference),
                "source": self.source, "relative_error": _finite(self.relative_error), "note": self.note}


def _finite(value):
    return float(value) if value is not None and math.isfinite(value) else None


def headline(scene, sim, out=None) -> list[Result]:
    """The headline results of `sim` (a run of `scene`) from its case's ``headline``
    function; [] for a scene not made by a case or a case without one."""
    from ..scene import catalogue

    case = getattr(scene, "case", "") or ""
    function = getattr(catalogue.case_module(case), "headline", None)
    if function is None or set(getattr(scene, "case_parameters", {})) != set(catalogue.parameters(case)):
        return []  # no such case (e.g. a scene file's factory), or a scene not made by it as it is now
    return list(function(sim, None if out is None else Path(out)))


def report(scene, sim, out) -> list[str]:
    """Lines to print about the headline results of `sim` (a finished run of `scene`),
    and, if `out` (the output folder) is not None, ``OUT/results.json`` written (whole,
    through a temporary file: never half-written). [] and nothing written for a scene
    without headline results (an earlier run's results.json there is removed). A headline
    that fails to compute is reported in one line (the run's own output stands)."""
    if out is not None:  # an earlier run's results in this folder would now be about another run
        (Path(out) / RESULTS_FILE).unlink(missing_ok=True)
    try:
        results = headline(scene, sim, out)
    except Exception as err:  # the run is done and written: say what failed, do not lose the run's exit
        return [f"headline results: not computed ({type(err).__name__}: {err})"]
    if not results:
        return []
    lines = ["headline results:"] + [f"  {r.line()}" for r in results]
    if out is not None:
        path = write(Path(out), scene, sim, results)
        lines[0] = f"headline results (also in {path}):"
    return lines


def write(folder: Path, scene, sim, results) -> Path:
    """Write ``folder/results.json``: the scene's name and case, the simulated time and
    steps, and ``results``: {name: {value, unit, reference, source, relative_error, note}}."""
    data = {"scene": scene.name, "case": getattr(scene, "case", ""), "time": float(sim.time),
            "steps": int(sim.steps), "results": {r.name: r.as_dict() for r in results}}
    folder.mkdir(parents=True, exist_ok=True)
    return write_text(folder / RESULTS_FILE, json.dumps(data, indent=2) + "\n")


def read(folder) -> dict:
    """A results.json as written by :func:`write`."""
    return json.loads((Path(folder) / RESULTS_FILE).read_text())


# --- helpers for the cases' headline functions --------------------------------------------
def probe_table(out, columns) -> dict | None:
    """{column: array} with ``time`` of the run's ``OUT/probes.csv`` (rows where every one of
    `columns` has a value), or None without an output folder, a probes.csv, those columns
    or two such rows."""
    if out is None or not (Path(out) / "probes.csv").is_file():
        return None
    from ..probes import read_csv

    table = read_csv(Path(out) / "probes.csv")
    if not all(c in table for c in ("time", *columns)):
        return None
    keep = np.all([np.isfinite(table[c]) for c in columns], axis=0) if columns else np.ones(len(table["time"]), bool)
    if np.count_nonzero(keep) < 2:
        return None
    return {c: np.asarray(table[c], float)[keep] for c in ("time", *columns)}


def sample_probes(sim, probes) -> dict:
    """One sample of `probes` (:class:`taisph.probes.Probe`) of the state `sim` holds now,
    as {column: value} with the columns of a probes.csv (``time``, ``NAME``, a force's
    ``NAME_x``...). Read only: a probe kernel reads the state; nothing is stepped or set."""
    from ..engine.layout import WALL
    from ..probes import Probes

    walls = {"walls": np.flatnonzero(sim.scene.kind == WALL), **sim.scene.wall_groups}
    writer = Probes(list(probes), walls=walls)
    try:
        writer.sample(sim)
        values = writer.values
        last = [v for p in writer.probes for v in np.ravel(values[p.name][-1])]
        row = dict(zip(["time", *writer.columns()], [float(writer.times[-1]), *last]))
    finally:
        writer.close()
    return row
