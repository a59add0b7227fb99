"""Progress display for long runs: a rich bar with simulated time, steps/s and ETA."""

from __future__ import annotations

import time


class Progress:
    """Context manager; ``update(t, steps)`` is cheap enough to call every step
    (the display refreshes at most ten times a second)."""

    def __init__(self, t0: float, t_end: float, enabled: bool = True, description: str = "simulating"):
        self.enabled = enabled
        self.t0, self.t_end = t0, t_end
        self.description = description
        self._next = 0.0

    def __enter__(self):
        if self.enabled:
            from rich.progress import BarColumn, Progress as RichProgress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

            self._bar = RichProgress(
                TextColumn("[bold]{task.description}"),
                BarColumn(),
                TextColumn("t = {task.fields[t]:.4f} / {task.total:.4g} s"),
                TextColumn("{task.fields[rate]:>7.0f} steps/s"),
                TimeElapsedColumn(),
                TextColumn("ETA"),
                TimeRemainingColumn(),
                transient=False,
            )
            self._bar.__enter__()
            self._task = self._bar.add_task(self.description, total=self.t_end, completed=self.t0, t=self.t0, rate=0.0)
            self._start = time.perf_counter()
        return self

    def update(self, t: float, steps: int, force: bool = False):
        if not self.enabled:
            return
        now = time.perf_counter()
        if now < self._next and not force:
            return
        self._next = now + 0.1
        rate = steps / (now - self._start) if now > self._start else 0.0
        self._bar.update(self._task, completed=t, t=t, rate=rate)

    def __exit__(self, *exc):
        if self.enabled:
            self._bar.__exit__(*exc)
        return False
