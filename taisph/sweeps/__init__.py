"""Parameter sweeps: the Cartesian product of parameter values, one run each, spread
over the worker processes of a Dask cluster (docs/sweeps.md).

    >>> import taisph
    >>> rows = taisph.sweep("hydrostatic_tank", vary={"dx": [0.1, 0.05]}, t_end=0.5,
    ...                     out="sweeps/tank", workers=2)            # doctest: +SKIP
    >>> [(r["dx"], r["status"], r["steps"], r["error"]) for r in rows]  # doctest: +SKIP

Command line: ``python -m taisph sweep CASE --vary NAME=v1,v2 ... --out DIR``
(:mod:`taisph.cli.sweep`). Modules: :mod:`.plan` (names, values, one task per
combination; no Dask), :mod:`.worker` (a run in a worker process), :mod:`.cluster`
(LocalCluster or an existing scheduler, results as runs finish), :mod:`.table`
(``sweep.csv``, ``sweep.md``, resume).
"""

from __future__ import annotations

from pathlib import Path

from . import table
from .plan import SweepError, Task, plan_tasks, value_text

__all__ = ["sweep", "SweepError", "Task", "plan_tasks"]


def sweep(case: str, vary: dict | None = None, client=None, *, out=None, workers: int | None = None,
          scheduler: str | None = None, validate: bool | None = None, frames_per_run: bool = False,
          retry_failed: bool = False, progress: bool = True, **fixed) -> list[dict]:
    """Run `case` once per combination of the values in `vary` and return one row per
    combination of this sweep (dicts, in the order the runs finished; resumed rows first).

    vary           {name: [values]}: case parameters (``dx``, ``kernel``, ...), run
                   settings (``precision``, ``dt``, ``threads``, ...; see
                   :data:`taisph.sweeps.plan.SETTINGS`) or, for validation runs, the
                   validation's keywords (``dt_factor``, ``T_end``, ...). Values may be
                   text, parsed as on the command line.
    **fixed        the same names, one value for every run (e.g. ``t_end=0.5``).
    client         a ``distributed.Client`` to run on; else `scheduler`
                   (``"tcp://host:port"``, an existing cluster); else a LocalCluster
                   of `workers` processes (default: one per core), closed afterwards.
    out            folder for ``sweep.csv``, ``sweep.md`` and ``sweep.json``, written
                   as runs finish; a sweep into a folder that already holds it skips
                   the combinations of its table (all of them, or with
                   `retry_failed` only those that were ok). A sweep that stops with an
                   exception (no cluster, Ctrl-C) before any run finished leaves none
                   of the three; a folder whose table holds no finished run takes a
                   different sweep (its files replaced), one with results refuses it.
                   None: no files.
    validate       each run is the case's validation (an ``error`` against its
                   reference; :mod:`taisph.validation`) or a plain run to the scene's
                   ``t_end``; default: validation when the case has a reference.
    frames_per_run write each plain run's frames to ``out/<run name>/``.

    A row holds ``run`` (its name), the varied values, ``status`` ("ok" or "failed:
    <first line of the diagnosis>"), ``steps``, ``wall_s`` (stepping only),
    ``particle_steps_per_s`` (fluid), ``wall_s_per_sim_s``, ``compile_s`` (building a
    simulation until its first step is done; kernels compile once per worker process
    and configuration), ``error`` (NaN without a reference), ``fluid_particles``,
    ``sim_time_s``, ``worker`` (host:pid) and ``error_name``. Bad input raises
    :class:`SweepError` before any run starts; a failed run never stops the others.
    """
    vary = dict(vary or {})
    folder = Path(out).resolve() if out is not None else None
    if frames_per_run and folder is None:
        raise SweepError("frames per run need an output folder (out=...)")
    tasks, validate = plan_tasks(case, vary, fixed, validate, str(folder) if folder else None, frames_per_run)
    varied = list(vary)
    done = []
    created = folder is not None and not folder.exists()
    if folder is not None:
        folder.mkdir(parents=True, exist_ok=True)
        identity = dict(case=case, validate=validate, varied=varied, frames_per_run=frames_per_run,
                        fixed={k: value_text(v) for k, v in _fixed_identity(tasks, varied).items()})
        table.check_identity(folder, identity)
        done = _resume(table.read(folder, varied), tasks, varied, retry_failed)
    names = {row["run"] for row in done}
    todo = [t for t in tasks if t.name not in names]
    rows = list(done)
    title = _title(case, validate, tasks, varied)

    def record(task, result):
        rows.append(_row(task, result, varied))
        if folder is not None:
            table.write(folder, varied, rows, title)

    try:
        if folder is not None:
            table.write(folder, varied, rows, title)
        if todo:
            from .cluster import connect, run_tasks

            with connect(client, workers, scheduler, len(todo)) as (dask_client, threads):
                run_tasks(todo, dask_client, threads, on_result=record, progress=progress,
                          title=f"sweep {case}")
    except BaseException:  # no cluster, an interruption...: a folder without a finished run is left empty
        if folder is not None and not table.has_results(folder):
            table.discard(folder)
            if created and not any(folder.iterdir()):
                folder.rmdir()
        raise
    planned = {t.name for t in tasks}
    return [row for row in rows if row["run"] in planned]


def _fixed_identity(tasks: list[Task], varied: list[str]) -> dict:
    """The values every run shares, but threads (it changes timings, not results)."""
    if not tasks:
        return {}
    first = tasks[0]
    everything = {**first.params, **first.settings}
    return {k: v for k, v in sorted(everything.items()) if k not in varied and k != "threads"}


def _resume(rows: list[dict], tasks: list[Task], varied: list[str], retry_failed: bool) -> list[dict]:
    """The table's rows to keep, their parameters as values again (matched to this
    sweep's combinations by run name); with `retry_failed`, the ok rows only."""
    by_name = {t.name: t for t in tasks}
    kept = []
    for row in rows:
        task = by_name.get(row["run"])
        if task is None:  # a combination of an earlier, larger sweep: keep it in the table
            kept.append(row)
            continue
        if retry_failed and row["status"] != "ok":
            continue
        row.update(task.combination)
        kept.append(row)
    return kept


def _row(task: Task, result: dict, varied: list[str]) -> dict:
    row = {"run": task.name, **{name: task.combination[name] for name in varied}}
    row.update({column: result[column] for column in table.COLUMNS})
    return row


def _title(case: str, validate: bool, tasks: list[Task], varied: list[str]) -> str:
    fixed = ", ".join(f"{k} = {value_text(v)}" for k, v in _fixed_identity(tasks, varied).items())
    kind = "validation runs (error against the case's reference)" if validate else "plain runs"
    return f"# Sweep of {case}\n\n{kind}; varied: {', '.join(varied) or 'nothing'}; fixed: {fixed or 'defaults'}."
