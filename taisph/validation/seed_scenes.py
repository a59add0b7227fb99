"""The seed's three scenes (report sec. 6) as they are measured: the resolutions at which
tests/test_seed_cases.py asserts their quantities and python -m tools.studies.seed_measure prints them
(docs/seed.md quotes both), the wedge's corners, and a recorder of a run's frames.
"""

from __future__ import annotations

from ..run.simulation import Simulation
from ..terms import STANDARD_GRAVITY

G = STANDARD_GRAVITY  # m/s^2, the cases' default gravity
DX_WEDGE = 0.04  # dam_break_wedge
DX_DROP = 0.02  # drop_on_incline (2D)
DX_TWO = 0.04  # two_fluids
WEDGE = ((2.0, 0.0), (2.5, 0.5), (3.0, 0.0))  # dam_break_wedge's default wedge: base corners and apex


def record(scene, t_end: float, frames: int):
    """Simulate `scene` to `t_end` and keep the state at t = 0 and at `frames` evenly
    spaced frames: ``(sim, snapshots)``, each snapshot a dict of t, x (positions),
    v (velocities), rho, m (masses) and mat (materials), in particle-id order."""
    sim = Simulation(scene)
    snaps = []

    def keep(s):
        snaps.append(dict(t=s.time, x=s.positions(), v=s.velocities(), rho=s.density(), m=s.masses(),
                          mat=s.materials()))

    keep(sim)
    sim.run(t_end, frames=frames, callback=keep)
    return sim, snaps


def at(snaps, t: float) -> dict:
    """The snapshot nearest time `t`."""
    return min(snaps, key=lambda s: abs(s["t"] - t))


def potential_energy(snapshot, fluid, g: float = G) -> float:
    """Gravitational potential energy sum m g y of the particles selected by `fluid`."""
    return float((snapshot["m"][fluid] * g * snapshot["x"][fluid, 1]).sum())
