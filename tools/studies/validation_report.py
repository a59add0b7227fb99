"""Run every validation case at the resolution the documentation quotes and write the
table of docs/validation.md's measured values.

    python -m tools.studies.validation_report                 # ~15 min on 2 cores; writes docs/validation_runs.md
    python -m tools.studies.validation_report --out /tmp/v.md --cases poiseuille couette

Each row: the case, its parameters, the headline error (as defined in
taisph.validation), the other metrics, particles, steps and the wall time spent stepping
(one run; on a shared machine timings vary by up to 2x).
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

import taisph  # noqa: E402
from taisph import validation  # noqa: E402

RUNS = [
    ("dam_break", dict(dx=0.02)),
    ("dam_break", dict(dx=0.02, walls="dummy")),
    ("dam_break", dict(dx=0.02, walls="dummy", wall_friction=True)),
    ("hydrostatic_tank", dict(dx=0.025, t_end=10.0, samples=50, delta=0.1)),
    ("hydrostatic_tank", dict(dx=0.025, t_end=10.0, samples=50, delta=None)),
    ("hydrostatic_tank", dict(dx=0.025, t_end=10.0, samples=50, delta=None, walls="lj")),
    ("poiseuille", dict(dx=5e-5)),
    ("poiseuille", dict(dx=2.5e-5)),
    ("couette", dict(dx=5e-5)),
    ("couette", dict(dx=2.5e-5)),
    ("taylor_green", dict(dx=1 / 50)),
    ("taylor_green", dict(dx=1 / 50, precision="f32")),
    ("taylor_green", dict(dx=1 / 50, delta=None)),
    ("taylor_green", dict(dx=1 / 50, shifting=False, delta=None)),
    ("elliptical_drop", dict(dx=0.025)),
    ("elliptical_drop", dict(dx=0.025, kernel="wendland")),
]


def fmt(v):
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.validation_report",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default=str(ROOT / "docs" / "validation_runs.md"))
    p.add_argument("--cases", nargs="+", choices=list(validation.VALIDATIONS))
    args = p.parse_args(argv)
    runs = [r for r in RUNS if not args.cases or r[0] in args.cases]
    load0 = os.getloadavg()[0]
    start = time.perf_counter()
    lines = []
    for case, params in runs:
        params = dict(params)
        precision = params.pop("precision", "f64")  # explicit: the runtime keeps the last precision otherwise
        out = validation.run(case, precision=precision, **params)
        if precision != "f64":
            params["precision"] = precision
        shown = ", ".join(f"{k}={fmt(v)}" for k, v in params.items())
        metrics = ", ".join(f"{k} {fmt(v)}" for k, v in out.metrics.items() if k != "t_end")
        err = "diverged" if out.diverged else fmt(out.error)
        lines.append(f"| {case} | {shown} | {err} | {metrics} | {out.fluid} | {out.steps} | {out.wall:.1f} |")
        print(lines[-1], flush=True)
    total = time.perf_counter() - start
    try:
        commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
    except Exception:
        commit = "unknown"
    command = ("python -m tools.studies.validation_report"
               + (" " + " ".join(argv if argv is not None else sys.argv[1:])).rstrip())
    text = [
        "# Validation runs",
        "",
        f"Made by `{command}` in {total / 60:.1f} min (taisph {taisph.__version__} at commit {commit}, "
        f"Python {platform.python_version()}, {os.cpu_count()} cores, 1-minute load average {load0:.1f} at the "
        f"start and {os.getloadavg()[0]:.1f} at the end: the machine was shared). Errors as defined in "
        "`taisph/validation/runs.py`; wall s: stepping only, one run.",
        "",
        "| case | parameters | error | metrics | fluid | steps | wall s |",
        "|---|---|---:|---|---:|---:|---:|",
        *lines,
        "",
    ]
    Path(args.out).write_text("\n".join(text))
    print(f"written {args.out} in {total / 60:.1f} min")


if __name__ == "__main__":
    main()
