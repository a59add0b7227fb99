"""Progress of a run: a rich bar with simulated time, steps/s and ETA while it runs, and
the summary of what it did."""

from __future__ import annotations

import time
from dataclasses import dataclass


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
