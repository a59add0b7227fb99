"""Progress of a run, on standard error: a rich bar with simulated time, steps/s and ETA
on a terminal; elsewhere (a log file, a pipe, a batch queue) a plain line every few
seconds (:data:`EVERY_VARIABLE`); and the summary of what the run did."""

from __future__ import annotations

import math
import os
import sys
import time
import warnings
from dataclasses import dataclass

from ..messages import TaisphWarning

# seconds between plain progress lines (stderr not a terminal); the first comes after at most FIRST
EVERY = 10.0
FIRST = 2.0
EVERY_VARIABLE = "TAISPH_PROGRESS_EVERY"  # the environment's choice of EVERY (seconds, > 0)


def line_interval(every: float | None = None) -> float:
    """Seconds between plain lines: `every`, else the environment's :data:`EVERY_VARIABLE`,
    else :data:`EVERY`; a variable that is not a number > 0 is named in a warning."""
    if every is not None:
        return float(every)
    text = os.environ.get(EVERY_VARIABLE, "").strip()
    if not text:
        return EVERY
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        warnings.warn(f"{EVERY_VARIABLE}={text!r} is not a number of seconds > 0; progress every {EVERY:g} s",
                      TaisphWarning, stacklevel=3)
        return EVERY
    return value


def clock(seconds: float) -> str:
    """``1:05`` or ``2:01:05`` (hours)."""
    seconds = max(0, int(round(seconds)))
    hours, rest = divmod(seconds, 3600)
    return f"{hours}:{rest // 60:02d}:{rest % 60:02d}" if hours else f"{rest // 60}:{rest % 60:02d}"


def plain_line(t0: float, t_end: float, t: float, steps: int, elapsed: float, description: str = "simulating") -> str:
    """One line of progress: simulated time of the end time, steps, steps/s, wall time
    elapsed and left (estimated from the simulated time's rate so far)."""
    span = t_end - t0
    done = (t - t0) / span if span > 0 else 1.0
    rate = steps / elapsed if elapsed > 0 else 0.0
    left = elapsed * (1 - done) / done if done > 0 else math.inf
    left_text = f"about {clock(left)} left" if math.isfinite(left) else "time left unknown yet"
    return (f"{description}: t = {t:.6g} / {t_end:.6g} s ({100 * done:.1f} %), {steps} steps, {rate:.0f} steps/s, "
            f"{clock(elapsed)} elapsed, {left_text}")


def is_terminal(stream) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):  # no isatty, or a closed stream
        return False


class Progress:
    """Context manager; ``update(t, steps)`` is cheap enough to call every step (the bar
    refreshes at most ten times a second, a plain line comes every `every` seconds).

    The display goes to `stream` (default ``sys.stderr``): a rich bar if it is a
    terminal, else plain lines (:func:`plain_line`), the first after ``min(FIRST,
    every)`` seconds, then every `every` seconds (:func:`line_interval`). `enabled`
    False: nothing at all."""

    def __init__(self, t0: float, t_end: float, enabled: bool = True, description: str = "simulating",
                 every: float | None = None, stream=None):
        self.enabled = enabled
        self.t0, self.t_end = t0, t_end
        self.description = description
        self.every, self.stream = every, stream
        self.plain = False
        self._next = 0.0

    def __enter__(self):
        if not self.enabled:
            return self
        stream = sys.stderr if self.stream is None else self.stream
        self._start = time.perf_counter()
        self.plain = not is_terminal(stream)
        if self.plain:
            self._stream, self.every = stream, line_interval(self.every)
            self._next = self._start + min(FIRST, self.every)
            return self
        from rich.console import Console
        from rich.progress import (BarColumn, Progress as RichProgress, TextColumn, TimeElapsedColumn,
                                   TimeRemainingColumn)

        self._bar = RichProgress(
            TextColumn("[bold]{task.description}"),
            BarColumn(),
            TextColumn("t = {task.fields[t]:.4f} / {task.total:.4g} s"),
            TextColumn("{task.fields[rate]:>7.0f} steps/s"),
            TimeElapsedColumn(),
            TextColumn("ETA"),
            TimeRemainingColumn(),
            transient=False,
            console=Console(file=stream),
        )
        self._bar.__enter__()
        self._task = self._bar.add_task(self.description, total=self.t_end, completed=self.t0, t=self.t0, rate=0.0)
        return self

    def update(self, t: float, steps: int, force: bool = False):
        """`t`: the simulated time now; `steps`: steps since the run began. `force`: refresh
        the bar now (a plain line still waits for its time)."""
        if not self.enabled:
            return
        now = time.perf_counter()
        if self.plain:
            if now >= self._next:
                self._next = now + self.every
                print(plain_line(self.t0, self.t_end, t, steps, now - self._start, self.description),
                      file=self._stream, flush=True)
            return
        if now < self._next and not force:
            return
        self._next = now + 0.1
        rate = steps / (now - self._start) if now > self._start else 0.0
        self._bar.update(self._task, completed=t, t=t, rate=rate)

    def __exit__(self, *exc):
        if self.enabled and not self.plain:
            self._bar.__exit__(*exc)
        return False


@dataclass
class RunSummary:
    """What :meth:`Simulation.run` did."""

    particles: int
    fluid_particles: int
    steps: int
    sim_time: float
    wall_time: float
    frames: int
    out: str | None
    dt_min: float = float("nan")
    dt_mean: float = float("nan")
    dt_max: float = float("nan")
    removed: int = 0  # particles removed so far (left the domain, or density out of range)
    list_rebuilds: int | None = None  # neighbour list rebuilds during the run (None: no lists)
    fluid_mass: float = float("nan")  # of the fluid particles still simulated, at the end
    removed_mass: float = 0.0  # of the particles removed so far
    # DFSPH: iterations per step, errors, steps above tolerance (dfsph.Stats.summary)
    pressure_solve: dict | None = None
    out_of_range: int = 0  # of `removed`: density out of the guard's range (taisph.engine.guards)
    replaced_frames: int = 0  # frames of an earlier series in `out` removed when this run began (run/vtk.py)
    open_mass: tuple | None = None  # open boundaries: (mass in, mass out) since the start, kg
    buffer_particles: int = 0  # open boundaries: particles in their buffers (of `particles`)

    @property
    def particle_steps_per_second(self) -> float:
        """Fluid particle-steps per wall second (the number SPH codes compare)."""
        return self.fluid_particles * self.steps / self.wall_time if self.wall_time > 0 else float("nan")

    def __str__(self) -> str:
        out = f", output in {self.out}" if self.out else ""
        if self.out and self.replaced_frames:
            out += f" (replaces an earlier run's series there: {self.replaced_frames} old frames removed)"
        removed = ""
        if self.list_rebuilds is not None:
            removed = f", neighbour lists rebuilt {self.list_rebuilds} times"
        removed += f", fluid mass {self.fluid_mass:.6g} kg"
        if self.removed:
            why = f"{self.removed} particles left the domain"
            if self.out_of_range:
                why = (f"{self.removed} particles: {self.removed - self.out_of_range} left the domain, "
                       f"{self.out_of_range} with density out of range")
            removed += f" + {self.removed_mass:.4g} kg removed ({why}) = {self.fluid_mass + self.removed_mass:.6g} kg"
        if self.open_mass is not None:
            removed += (f" (open boundaries since t = 0: {self.open_mass[0]:.6g} kg in, {self.open_mass[1]:.6g} kg "
                        "out)")
        if self.pressure_solve:
            ps = self.pressure_solve
            removed += (f", DFSPH iterations per step: density {ps['density_iterations_mean']:.1f} (max "
                        f"{ps['density_iterations_max']}), divergence {ps['divergence_iterations_mean']:.1f} (max "
                        f"{ps['divergence_iterations_max']}), mean density error reached <= "
                        f"{100 * ps['density_error_max']:.3g} %")
            if ps.get("steps_above_tolerance"):
                removed += (f", {ps['steps_above_tolerance']} steps kept with a solve above its tolerance (worst "
                            f"{ps['worst_over_tolerance']:.3g} times it)")
            if ps.get("retries"):
                removed += f", {ps['retries']} steps retried with half the dt (a solve ended beyond the bound)"
        return (
            f"{self.fluid_particles} fluid + "
            + (f"{self.buffer_particles} open-boundary buffer + " if self.buffer_particles else "")
            + f"{self.particles - self.fluid_particles - self.buffer_particles} wall particles, "
            f"{self.steps} steps to t = {self.sim_time:.4g} s in {self.wall_time:.2f} s wall "
            f"({self.particle_steps_per_second / 1e6:.2f} M fluid particle-steps/s), "
            f"dt min/mean/max {self.dt_min:.3g}/{self.dt_mean:.3g}/{self.dt_max:.3g} s, "
            f"{self.frames} frames{removed}{out}"
        )
