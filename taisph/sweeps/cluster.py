"""Running tasks on a Dask cluster: a LocalCluster of worker processes, or an existing
cluster given by its scheduler's address (``dask scheduler`` / ``dask worker``).

Each task (:class:`taisph.sweeps.plan.Task`) is one Dask task calling
:func:`taisph.sweeps.worker.run_task` in a worker process; results come back as runs
finish (``distributed.as_completed``). A worker that dies (a crash, memory) is a
failed run, not a failed sweep.
"""

from __future__ import annotations

import contextlib
import dataclasses
import logging
import os
import sys
import uuid
import warnings

from ..messages import TaisphWarning
from .plan import SweepError, Task
from .worker import blank_result, fail, run_task

WORKER_WAIT_S = 60  # how long an existing cluster may take to show a worker


def default_workers(tasks: int) -> int:
    """One worker process per core, no more than there are runs."""
    return max(1, min(os.cpu_count() or 1, tasks))


@contextlib.contextmanager
def connect(client=None, workers: int | None = None, scheduler: str | None = None, tasks: int = 1):
    """Yield ``(client, threads)``: a Dask client and the default CPU threads per run.

    With `client`, that client (the caller's cluster; 1 thread per run); with
    `scheduler` (``tcp://host:port``), a client of that cluster (1 thread per run:
    start workers with ``--nthreads 1`` and as many ``--nworkers`` as runs should
    share a machine); else a LocalCluster of `workers` processes with one Dask
    thread each, closed afterwards, each run using its share of the cores."""
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise SweepError("sweeps run on Dask: pip install 'taisph[sweep]' (or: pip install distributed)") from None
    if client is not None and scheduler is not None:
        raise SweepError("give a client or a scheduler address, not both")
    if client is not None:
        _check_workers(client)
        yield client, 1
        return
    if scheduler is not None:
        try:
            own = Client(scheduler, timeout="10s")
        except (OSError, ValueError) as err:  # no answer, or not an address
            raise SweepError(f"cannot reach the Dask scheduler at {scheduler}: {err}") from None
        with own:
            _check_workers(own, scheduler)
            yield own, 1
        return
    workers = workers or default_workers(tasks)
    if workers < 1:
        raise SweepError(f"workers must be at least 1, got {workers}")
    import dask

    # no Taichi banner per worker: set before each worker process starts, as it may import
    # taichi while it loads the starting script (python -m tools.studies.accuracy_cost)
    with dask.config.set({"distributed.nanny.pre-spawn-environ.ENABLE_TAICHI_HEADER_PRINT": "0"}):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR)
    with cluster, Client(cluster) as own:
        yield own, max(1, (os.cpu_count() or 1) // workers)


def _check_workers(client, address: str | None = None) -> None:
    try:
        client.wait_for_workers(1, timeout=WORKER_WAIT_S)
    except TimeoutError:
        raise SweepError(f"no Dask worker joined the scheduler {address or client.scheduler.address} within "
                         f"{WORKER_WAIT_S} s; start some: dask worker ADDRESS --nworkers N --nthreads 1") from None
    busy = {addr: n for addr, n in client.nthreads().items() if n > 1}
    if busy:
        listed = ", ".join(f"{address}: {n}" for address, n in busy.items())
        warnings.warn(f"{len(busy)} Dask worker(s) have more than one thread ({listed}); "
                      "a worker process runs one taisph run at a time (Taichi's runtime belongs to a process), so "
                      "the other threads stay idle: start workers with --nthreads 1 --nworkers N",
                      TaisphWarning, stacklevel=3)


def run_tasks(tasks: list[Task], client, threads: int | None = None, on_result=None, progress: bool = False,
              title: str = "sweep") -> list[dict]:
    """Run `tasks` on `client`'s cluster; return their results in the order they
    finished. A task without a ``threads`` setting gets `threads`. `on_result(task,
    result)` is called as each run finishes (in this process)."""
    from distributed import as_completed

    batch = uuid.uuid4().hex[:8]
    # Taichi reinitialises when a process changes precision: submit runs of one precision together
    order = sorted(range(len(tasks)), key=lambda k: tasks[k].settings.get("precision", "f64") != "f64")
    futures = {}
    for rank, k in enumerate(order):
        task = tasks[k]
        if threads is not None and task.settings.get("threads") is None:
            task = dataclasses.replace(task, settings={**task.settings, "threads": threads})
        future = client.submit(run_task, task, key=f"taisph-{batch}-{k}", pure=False, priority=len(tasks) - rank)
        futures[future] = task
    results = []
    with _progress_bar(progress, len(tasks), title) as bar:
        for future in as_completed(futures):
            task = futures[future]
            try:
                result = future.result()
            except Exception as err:  # the worker died, or the task could not reach one
                result = blank_result(task)
                result["worker"] = ""
                fail(result, err)
            results.append(result)
            if on_result is not None:
                on_result(task, result)
            bar(task, result)
    return results


@contextlib.contextmanager
def _progress_bar(enabled: bool, total: int, title: str):
    """Yield ``update(task, result)``: a rich progress bar over runs, with a line per
    finished run above it (or nothing when not `enabled`)."""
    if not enabled:
        yield lambda task, result: None
        return
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, \
        TimeRemainingColumn

    columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TextColumn("runs"),
               TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn())
    with Progress(*columns, console=Console(file=sys.stderr)) as bar:
        job = bar.add_task(title, total=total)

        def update(task, result):
            done = "ok" if result["status"] == "ok" else result["status"]
            error = f", error {result['error']:.4g}" if result["status"] == "ok" and result["error_name"] else ""
            bar.console.print(f"{task.name}: {done} ({result['steps']} steps, {result['wall_s']:.3g} s{error})",
                              highlight=False, markup=False)
            bar.advance(job)

        yield update
