"""A sweep's table: ``DIR/sweep.csv``, ``DIR/sweep.md`` and ``DIR/sweep.json``.

Both tables are rewritten whole after every finished run, into a temporary file
renamed over the old one, so a reader (or a sweep killed half-way) never sees a
half-written row. ``sweep.json`` records what the sweep is (case, varied names,
fixed values, validation or plain runs): a rerun into the same folder must be the
same sweep, and then skips the combinations its table already holds. A sweep that
stops with an exception before any of its runs finished removes the three files
again, and a folder whose table holds no finished run takes another sweep.
"""

from __future__ import annotations

import csv
import io
import json
import math
import warnings
from pathlib import Path

from ..messages import TaisphWarning
from ..run.atomic import write_text
from .plan import SweepError, value_text

# the measured columns, after the run's name and its varied parameters
COLUMNS = ["status", "steps", "wall_s", "particle_steps_per_s", "wall_s_per_sim_s", "compile_s", "error",
           "fluid_particles", "sim_time_s", "worker", "error_name"]
INTEGER_COLUMNS = ("steps", "fluid_particles")
FLOAT_COLUMNS = ("wall_s", "particle_steps_per_s", "wall_s_per_sim_s", "compile_s", "error", "sim_time_s")
# markdown headers of the columns
HEADERS = {"status": "status", "steps": "steps", "wall_s": "wall s", "particle_steps_per_s": "particle-steps/s",
           "wall_s_per_sim_s": "wall s / sim s", "compile_s": "compile s", "error": "error",
           "fluid_particles": "fluid", "sim_time_s": "sim s", "worker": "worker"}


def fieldnames(varied: list[str]) -> list[str]:
    return ["run", *varied, *COLUMNS]


def _cell(value) -> str:
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else str(value)
    return "" if value is None else str(value)


def write(folder: Path, varied: list[str], rows: list[dict], title: str) -> None:
    """Rewrite DIR/sweep.csv and DIR/sweep.md with `rows` (dicts with fieldnames(varied) keys)."""
    names = fieldnames(varied)
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=names, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: value_text(row[k]) if k in varied else _cell(row.get(k)) for k in names})
    write_text(folder / "sweep.csv", buffer.getvalue())
    write_text(folder / "sweep.md", markdown(varied, rows, title))


def _short(value) -> str:
    if isinstance(value, float):
        if math.isnan(value):
            return "–"
        return f"{value:.4g}"
    return str(value)


def markdown(varied: list[str], rows: list[dict], title: str) -> str:
    shown = [c for c in COLUMNS if c not in ("error_name", "sim_time_s")]
    if not any(isinstance(r.get("error"), float) and not math.isnan(r["error"]) for r in rows):
        shown.remove("error")
    lines = [title, ""]
    names = sorted({r["error_name"] for r in rows if r.get("error_name")})
    if names and "error" in shown:
        lines += [f"error: {'; '.join(names)}", ""]
    lines.append("| " + " | ".join([*varied, *(HEADERS[c] for c in shown)]) + " |")
    lines.append("|" + "|".join(["---"] * len(varied) + [("---" if c in ("status", "worker") else "---:")
                                                         for c in shown]) + "|")
    for row in rows:
        cells = [value_text(row[n]) for n in varied]
        failed = row.get("status") != "ok"  # a failed run's counts are unknown, not 0
        cells += ["–" if failed and c in INTEGER_COLUMNS else _short(row.get(c)).replace("|", "\\|") for c in shown]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def read(folder: Path, varied: list[str]) -> list[dict]:
    """The rows of DIR/sweep.csv (measured numbers as numbers, parameters as their
    text: :func:`taisph.sweeps.plan.value_text`), or []."""
    path = folder / "sweep.csv"
    if not path.exists():
        return []
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        if reader.fieldnames != fieldnames(varied):
            raise SweepError(f"{path} has the columns {reader.fieldnames}, not those of this sweep "
                             f"{fieldnames(varied)}; give another output folder")
        rows = list(reader)
    for row in rows:
        for column in INTEGER_COLUMNS:
            row[column] = int(row[column]) if row[column] else 0
        for column in FLOAT_COLUMNS:
            row[column] = float(row[column]) if row[column] else math.nan
    return rows


def _flat(identity: dict) -> dict:
    """{"case": .., "fixed": {"t_end": ..}} -> {"case": .., "t_end": ..}: what differs, by name."""
    flat = {k: v for k, v in identity.items() if k != "fixed"}
    flat.update(identity.get("fixed", {}))
    return flat


FILES = ("sweep.csv", "sweep.md", "sweep.json")  # what a sweep writes into its folder (besides frames)


def has_results(folder: Path) -> bool:
    """Does DIR/sweep.csv hold a run that finished ("ok")? A table of failed runs only, or
    none, holds nothing a rerun would keep that it could not remake."""
    path = folder / "sweep.csv"
    if not path.exists():
        return False
    with open(path, newline="") as f:
        return any(row.get("status") == "ok" for row in csv.DictReader(f))


def discard(folder: Path) -> None:
    """Remove DIR/sweep.csv, sweep.md and sweep.json (and a temporary file left by a killed write)."""
    for name in FILES:
        (folder / name).unlink(missing_ok=True)
        for tmp in folder.glob(f".{name}.*.tmp"):
            tmp.unlink(missing_ok=True)


def check_identity(folder: Path, identity: dict) -> None:
    """Write DIR/sweep.json, or check that an earlier sweep into `folder` was this one. A
    different sweep is refused while the folder holds results (:func:`has_results`); the
    files of one without (every run failed, or none finished) are replaced, with a warning."""
    path = folder / "sweep.json"
    if path.exists():
        before = json.loads(path.read_text())
        if before != identity and not has_results(folder):
            warnings.warn(f"{folder} held another sweep ({before.get('case')}) without a finished run; its "
                          "sweep.csv, sweep.md and sweep.json are replaced", TaisphWarning, stacklevel=3)
            discard(folder)
        elif before != identity:
            was, now = _flat(before), _flat(identity)
            changed = sorted(k for k in set(was) | set(now) if was.get(k) != now.get(k))
            detail = "; ".join(f"{k}: was {was.get(k)!r}, now {now.get(k)!r}" for k in changed)
            raise SweepError(f"{folder} holds another sweep ({detail}); resume it with the same case and options, "
                             "or give another output folder")
        else:
            return
    write_text(path, json.dumps(identity, indent=2, sort_keys=True) + "\n")
