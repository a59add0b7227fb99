"""What a simulation's state reads as on the host: numpy arrays in particle-id order,
the masks of fluid, wall and buffer particles, and the sums made of them."""

import numpy as np

from ..engine import status as st
from ..engine.layout import FLUID, WALL


class Readout:
    """The host-side reading of :class:`taisph.Simulation`'s state (a mixin: it uses the
    simulation's ``state``, ``solver``, ``steps`` and ``time``)."""

    # --- state as numpy, in particle-id order ------------------------------------
    def _arrays(self):
        """All stored quantities as numpy, in particle-id order (cached per step)."""
        key = (self.steps, self.time)
        if self._snapshot_key != key:
            self._snapshot = self.state.to_numpy()
            self._snapshot_key = key
        return self._snapshot

    def quantity(self, name: str) -> np.ndarray:
        """Any stored per-particle quantity by name, in particle-id order."""
        kind = self.solver.layout.kind_of(name)
        group = {"vector": 0, "scalar": 1, "integer": 2}[kind]
        return self._arrays()[group][getattr(self.solver.layout.q, name)].copy()

    def positions(self) -> np.ndarray:
        """(N, dim) positions in particle-id order (the scene's); NaN for removed particles."""
        return self.quantity("position")

    def velocities(self) -> np.ndarray:
        return self.quantity("velocity")

    def density(self) -> np.ndarray:
        return self.quantity("density")

    def pressure(self) -> np.ndarray:
        """Pressure from the equation of state at the current density."""
        return self.quantity("pressure")

    def masses(self) -> np.ndarray:
        return self.quantity("mass")

    def ids(self) -> np.ndarray:
        return self.quantity("id")

    def materials(self) -> np.ndarray:
        return self.quantity("material")

    def kinds(self) -> np.ndarray:
        return self.quantity("kind")

    @property
    def fluid(self) -> np.ndarray:
        """Boolean mask of (active) fluid particles, in particle-id order (not open
        boundaries' buffer particles: :attr:`buffer`)."""
        fluid = self.kinds() == FLUID
        return fluid & (self.quantity("open_zone") == 0) if self.solver.open is not None else fluid

    @property
    def buffer(self) -> np.ndarray:
        """Boolean mask of open boundaries' buffer particles (all False without)."""
        return (self.kinds() == FLUID) & ~self.fluid

    def open_boundary_mass(self) -> tuple:
        """(mass that entered the fluid through open boundaries, mass that left it), kg since the start."""
        return self.state.read(st.MASS_IN), self.state.read(st.MASS_OUT)

    @property
    def wall(self) -> np.ndarray:
        return self.kinds() == WALL

    def total_mass(self) -> float:
        return float(self.masses()[self.fluid].sum())

    def momentum(self) -> np.ndarray:
        m = self.masses()[self.fluid]
        return (m[:, None] * self.velocities()[self.fluid]).sum(axis=0)

    def kinetic_energy(self) -> float:
        m = self.masses()[self.fluid]
        v = self.velocities()[self.fluid]
        return float(0.5 * (m * (v * v).sum(axis=1)).sum())
