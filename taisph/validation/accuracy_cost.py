"""Work-precision study: what each choice buys in accuracy and costs in wall time.

For every validation case (:mod:`taisph.validation.runs`) :func:`run_study` runs a
baseline configuration and one-factor-at-a-time variations of it (kernel, integrator,
precision, wall model, density diffusion, ...) at several resolutions, and records for
each run the error against the case's reference, the wall time spent stepping (kernel
compilation and set-up excluded, reported apart), the number of steps and the fluid
particle-steps per second. It writes, in the output folder,

    accuracy_cost.csv      one row per run
    accuracy_cost.md       a table per case, with the observed convergence order of
                           every configuration (least-squares slope of log error
                           against log dx)
    wp_<case>.png          work-precision plot: error against wall time, log-log,
                           one line per configuration, one point per resolution

Every run is a task of taisph's sweeps (:mod:`taisph.sweeps`) in a Dask worker process:
by default one local worker, so runs go one at a time on all cores as they always did;
``workers`` N runs N at a time, ``scheduler`` (an address) spreads them over an
existing cluster (``docs/sweeps.md``). ``setup_s`` is the sweep's compile time:
building a simulation until its first step is done (kernels compile once per worker
process and configuration). Runs are grouped by precision (Taichi's precision is
process-wide). Each wall time is one run (``repeat`` N takes the median of N): on a
shared machine small differences of time are noise (docs/accuracy.md, "How to read
the times"). The command line is
``python -m tools.studies.accuracy_cost`` (docs/accuracy.md); ``quick=True`` is its CI mode,
which tests/test_accuracy_study.py runs.
"""

from __future__ import annotations

import csv
import json
import math
import os
import platform
import statistics
import subprocess
import time
from importlib.metadata import version
from pathlib import Path

import numpy as np

from .study_plan import F32, F64, QUICK_CASES, QUICK_VARIANTS, STUDY  # noqa: F401 (the plan, re-exported)

ROOT = Path(__file__).resolve().parents[2]  # the source checkout, if taisph runs from one (git_commit)


FIELDS = ["case", "config", "precision", "dx", "fluid_particles", "particles", "steps", "dt", "wall_s", "setup_s",
          "particle_steps_per_s", "error", "error_name", "diverged", "params", "metrics", "failure"]


def variants_of(case, quick, only=None):
    """The configurations of `case` the study runs: all, the first QUICK_VARIANTS with
    `quick`, or those whose label contains one of the words of `only`."""
    variants = STUDY[case]["variants"][:QUICK_VARIANTS] if quick else STUDY[case]["variants"]
    if only:
        variants = [v for v in variants if any(word in v[0] for word in only)]
    return variants


def plan(cases, quick, only=None):
    runs = []
    for case in cases:
        spec = STUDY[case]
        variants = variants_of(case, quick, only)
        levels = spec["quick"] if quick else spec["levels"]
        for label, change, precision in variants:
            params = {**spec["fixed"], **spec["base"], **change}
            params = {k: v for k, v in params.items() if v is not None or k in ("delta",)}
            for dx in levels:
                runs.append(dict(case=case, config=label, precision=precision, dx=dx, params={**params, "dx": dx}))
    # Taichi's precision is process-wide: all f64 runs first, then all f32 runs
    runs.sort(key=lambda r: r["precision"] != F64)
    return runs


def tasks_of(runs, repeat):
    """The study's runs as sweep tasks (validation runs), `repeat` tasks per run."""
    from ..sweeps import Task

    return [Task(run["case"], f"{run['case']} {run['config']} dx={run['dx']:g} #{k}", dict(run["params"]),
                 {"precision": run["precision"]}, validate=True, tag=(index, k))
            for index, run in enumerate(runs) for k in range(repeat)]


def row_of(run, results):
    """The table row of `run` from its repeats' results (sweep results,
    :func:`taisph.sweeps.worker.run_task`): the median wall time; a run that failed
    (not diverged: that is an error of inf) is a row with its failure."""
    out = results[-1]
    failed = [r for r in results if r["status"] != "ok" and not r["diverged"]]
    if failed:
        return dict(case=run["case"], config=run["config"], precision=run["precision"], dx=run["dx"],
                    fluid_particles=0, particles=0, steps=0, dt=float("nan"), wall_s=float("nan"),
                    setup_s=float("nan"), particle_steps_per_s=float("nan"), error=float("nan"), error_name="",
                    diverged=False, params=json.dumps(run["params"], sort_keys=True), metrics="{}",
                    failure=failed[0]["failure"])
    wall = statistics.median(r["wall_s"] for r in results)
    return dict(
        case=run["case"], config=run["config"], precision=out["precision"], dx=run["dx"],
        fluid_particles=out["fluid_particles"], particles=out["particles"], steps=out["steps"], dt=out["dt"],
        wall_s=wall, setup_s=out["compile_s"],
        particle_steps_per_s=out["fluid_particles"] * out["steps"] / wall if wall > 0 else float("nan"),
        error=out["error"], error_name=out["error_name"], diverged=out["diverged"],
        params=json.dumps(run["params"], sort_keys=True), metrics=json.dumps(out["metrics"], sort_keys=True),
        failure="",
    )


def observed_order(rows):
    """Least-squares slope of log(error) against log(dx) over finite, positive errors."""
    pts = [(r["dx"], r["error"]) for r in rows if math.isfinite(r["error"]) and r["error"] > 0]
    if len(pts) < 2:
        return float("nan")
    x = np.log([p[0] for p in pts])
    y = np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0])


def fmt(v, digits=3):
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "diverged" if v == float("inf") else "–"
    if isinstance(v, int):
        return str(v)
    return f"{v:.{digits}g}"


def write_markdown(path, rows, header):
    lines = [header, ""]
    for case in dict.fromkeys(r["case"] for r in rows):
        cr = [r for r in rows if r["case"] == case]
        lines += [f"## {case}", "", f"Error: {next((r['error_name'] for r in cr if r['error_name']), '')}.", ""]
        lines += ["| configuration | dx | fluid | steps | wall s | M particle-steps/s | error | order |",
                  "|---|---:|---:|---:|---:|---:|---:|---:|"]
        for config in dict.fromkeys(r["config"] for r in cr):
            rr = [r for r in cr if r["config"] == config]
            p = observed_order(rr)
            for k, r in enumerate(rr):
                err = "diverged" if r["diverged"] else ("failed" if r["failure"] else fmt(r["error"]))
                lines.append(f"| {config if k == 0 else ''} | {r['dx']:.4g} | {r['fluid_particles']} | {r['steps']} | "
                             f"{fmt(r['wall_s'])} | {fmt(r['particle_steps_per_s'] / 1e6)} | {err} | "
                             f"{fmt(p, 2) if k == 0 else ''} |")
        lines.append("")
    path.write_text("\n".join(lines))


def write_plots(folder, rows):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    for case in dict.fromkeys(r["case"] for r in rows):
        cr = [r for r in rows if r["case"] == case]
        fig, ax = plt.subplots(figsize=(6.4, 4.6))
        markers = "osD^v<>ph*"
        for k, config in enumerate(dict.fromkeys(r["config"] for r in cr)):
            rr = [r for r in cr if r["config"] == config and math.isfinite(r["error"]) and r["error"] > 0]
            if not rr:
                continue
            ax.loglog([r["wall_s"] for r in rr], [r["error"] for r in rr], marker=markers[k % len(markers)],
                      label=f"{config} (p = {fmt(observed_order(rr), 2)})")
            for r in rr:
                ax.annotate(f"{r['dx']:.3g}", (r["wall_s"], r["error"]), fontsize=6, alpha=0.6,
                            xytext=(2, 2), textcoords="offset points")
        ax.set_xlabel("wall time of the run, s (stepping only)")
        ax.set_ylabel(cr[0]["error_name"] if cr[0]["error_name"] else "error")
        ax.set_title(f"{case}: error vs cost (labels: dx; p: observed order in dx)", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6.5, loc="best")
        fig.tight_layout()
        path = folder / f"wp_{case}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    return written


def git_commit():
    try:
        return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except Exception:
        return "unknown"


def run_study(out, cases=None, quick: bool = False, repeat: int = 1,
              command: str = "taisph.validation.accuracy_cost.run_study", workers: int = 1,
              scheduler: str | None = None, threads: int | None = None, client=None, only=None) -> list[dict]:
    """Run the study of `cases` (default: all; with `quick`: dam_break and poiseuille,
    two configurations each, small sizes), write its CSV, table and plots in folder
    `out`, print one line per run, and return the rows. `command` is how the study was
    started, for the table's header. A run that fails is a row with its failure.

    The runs are sweep tasks (:func:`taisph.sweeps.cluster.run_tasks`): on `client`
    (a ``distributed.Client``), else on the cluster at `scheduler`, else on a
    LocalCluster of `workers` processes. `threads`: CPU threads per run (default:
    cores / workers on a LocalCluster, 1 on an existing cluster)."""
    from ..sweeps.cluster import connect, run_tasks

    cases = list(cases or (QUICK_CASES if quick else STUDY))
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    runs = plan(cases, quick, only)
    cases = [c for c in cases if any(r["case"] == c for r in runs)]
    print(f"{len(runs)} runs: {', '.join(cases)}", flush=True)
    load_start = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    start = time.perf_counter()
    rows, results, used_threads = [], {}, set()
    tasks = tasks_of(runs, repeat)

    def finished(task, result):  # a run's last repeat finishing makes its row
        index, _ = task.tag
        results.setdefault(index, []).append(result)
        if result["threads"] is not None:
            used_threads.add(result["threads"])
        if len(results[index]) < repeat:
            return
        row = row_of(runs[index], results[index])
        rows.append(row)
        print(f"[{len(rows)}/{len(runs)}] {row['case']:16s} {row['config']:44s} dx={row['dx']:<8.4g} "
              f"error={fmt(row['error'])} wall={fmt(row['wall_s'])} s (compile {fmt(row['setup_s'])} s) "
              f"{row['failure']}", flush=True)

    with connect(client, workers=workers, scheduler=scheduler, tasks=len(tasks)) as (dask_client, default_threads):
        run_tasks(tasks, dask_client, threads or default_threads, on_result=finished)
    total = time.perf_counter() - start
    load_end = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    # table order: per case, configurations and resolutions as listed in STUDY (the f32 runs
    # were only moved to the end to run them together)
    order = {}
    for case in cases:
        spec = STUDY[case]
        for label, _, _ in variants_of(case, quick, only):
            for dx in (spec["quick"] if quick else spec["levels"]):
                order[(case, label, dx)] = len(order)
    rows.sort(key=lambda r: order[(r["case"], r["config"], r["dx"])])

    with open(folder / "accuracy_cost.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    import taichi as ti

    taichi_version = ".".join(map(str, ti.__version__))
    header = (f"# Accuracy and cost\n\nMade by `{command}` in {total / 60:.1f} min "
              f"(taisph {version('taisph')} at commit {git_commit()}, taichi {taichi_version}, "
              f"Python {platform.python_version()}, {os.cpu_count()} cores, "
              f"{'/'.join(map(str, sorted(used_threads))) or '?'} thread(s) per run, "
              f"{'cluster' if scheduler or client else workers} run(s) at a time). Wall time: stepping only, "
              f"{'median of %d runs' % repeat if repeat > 1 else 'one run'} per point, on a shared machine "
              f"(1-minute load average {load_start:.1f} at the start, {load_end:.1f} at the end, on "
              f"{os.cpu_count()} cores: other jobs shared the machine; differences below ~30 % are noise). "
              f"Order: least-squares slope of log(error) against log(dx).")
    write_markdown(folder / "accuracy_cost.md", rows, header)
    plots = write_plots(folder, rows)
    print(f"done in {total / 60:.1f} min: {folder / 'accuracy_cost.csv'}, {folder / 'accuracy_cost.md'}, "
          f"{len(plots)} plots", flush=True)
    return rows
