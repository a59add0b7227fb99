"""The result of a validation run (:mod:`taisph.validation.runs`): its error against the
reference, the metrics computed on the way, and its cost."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Outcome:
    case: str
    params: dict
    precision: str
    error: float
    error_name: str
    metrics: dict = field(default_factory=dict)
    fluid: int = 0
    particles: int = 0
    steps: int = 0
    dt: float = float("nan")
    dx: float = float("nan")
    wall: float = 0.0  # seconds spent stepping
    setup: float = 0.0  # seconds to build the simulation (kernel compilation included)
    sim_time: float = 0.0  # simulated time reached (s)
    series: dict = field(default_factory=dict)
    diverged: bool = False

    @property
    def rate(self) -> float:
        """Fluid particle-steps per wall second."""
        return self.fluid * self.steps / self.wall if self.wall > 0 else float("nan")
