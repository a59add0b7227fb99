"""What a simulation's state reads as on the host: numpy arrays in particle-id order,
the masks of fluid, wall and buffer particles, and the sums made of them."""

import collections

import numpy as np

from ..engine import status as st
from ..engine.layout import FLUID, WALL


BodyState = collections.namedtuple("BodyState", "position orientation velocity angular_velocity force torque mass")
BodyState.__doc__ = """A body's state (:meth:`Readout.bodies`): its reference point (centre of mass of
a floating body, pivot of a prescribed one, m), orientation (2D: angle, rad; 3D: unit
quaternion (w, x, y, z)), velocity (m/s), angular velocity (2D: rad/s about z; 3D: a
vector), the fluid's and contacts' force (N; per metre in 2D) and torque of the last step
(gravity not included), and its mass (kg; per metre in 2D)."""


class Readout:
    """The host-side reading of :class:`taisph.Simulation`'s state (a mixin: it uses the
    simulation's ``state``, ``solver``, ``steps`` and ``time``)."""

    # --- state as numpy, in particle-id order ------------------------------------
    def open_state(self):
        """The device state, or a clear error if :meth:`close` freed it."""
        if getattr(self, "state", None) is None:
            raise RuntimeError("this simulation was closed (Simulation.close freed its state): read what you need "
                               "before closing it, or build a new Simulation")
        return self.state

    def _arrays(self):
        """All stored quantities as numpy, in particle-id order (cached per step)."""
        key = (self.steps, self.time)
        if self._snapshot_key != key:
            self.open_state()
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
        for row in self.solver.imposed_rows:  # a term's imposed particles (Term.imposed_row)
            fluid &= self._arrays()[2][row] == 0
        return fluid

    @property
    def buffer(self) -> np.ndarray:
        """Boolean mask of open boundaries' buffer particles (all False without)."""
        return (self.kinds() == FLUID) & ~self.fluid

    def open_boundary_mass(self) -> tuple:
        """(mass that entered the fluid through open boundaries, mass that left it), kg since the start."""
        slot = self.solver.status_slot
        return self.state.read(slot("open_boundaries", "mass_in")), self.state.read(slot("open_boundaries", "mass_out"))

    @property
    def wall(self) -> np.ndarray:
        return self.kinds() == WALL

    def total_mass(self) -> float:
        return float(self.masses()[self.fluid].sum())

    def momentum(self) -> np.ndarray:
        m = self.masses()[self.fluid]
        return (m[:, None] * self.velocities()[self.fluid]).sum(axis=0)

    def bodies(self) -> dict:
        """Each body's :class:`BodyState` now, by name (empty without bodies)."""
        if "bodies" not in self.solver.device_arrays:
            return {}
        from ..terms import rigid_bodies as rb

        values = self.state.read_array("bodies")
        d = self.dim
        out = {}
        for k, body in enumerate(self.scene.bodies):
            row = values[k * rb.BODY_COLS:(k + 1) * rb.BODY_COLS]
            out[body.name] = BodyState(
                position=row[rb.CENTRE:rb.CENTRE + d].copy(),
                orientation=float(row[rb.ORIENTATION]) if d == 2 else row[rb.ORIENTATION:rb.ORIENTATION + 4].copy(),
                velocity=row[rb.VELOCITY:rb.VELOCITY + d].copy(),
                angular_velocity=float(row[rb.OMEGA + 2]) if d == 2 else row[rb.OMEGA:rb.OMEGA + 3].copy(),
                force=row[rb.FORCE:rb.FORCE + d].copy(),
                torque=float(row[rb.TORQUE + 2]) if d == 2 else row[rb.TORQUE:rb.TORQUE + 3].copy(),
                mass=body.mass)
        return out

    def momentum_with_bodies(self) -> np.ndarray:
        """Linear momentum of the fluid and the floating bodies (kg m/s; per metre in 2D)."""
        total = self.momentum()
        for body, state in zip(self.scene.bodies, self.bodies().values()):
            if body.motion == "floating":
                total = total + body.mass * (state.velocity + _hinged_mass_centre_velocity(body, state))
        return total

    def kinetic_energy(self) -> float:
        m = self.masses()[self.fluid]
        v = self.velocities()[self.fluid]
        return float(0.5 * (m * (v * v).sum(axis=1)).sum())


def _hinged_mass_centre_velocity(body, state) -> np.ndarray:
    """omega x (R r_c): the velocity of a hinged body's centre of mass (its reference point,
    the hinge, does not move); zero for a body whose reference is its centre of mass."""
    if body.hinge is None:
        return 0.0
    r = np.asarray(body.centre_of_mass, float)
    if len(r) == 2:
        from ..scene.bodies import _rotation

        r = _rotation(2, state.orientation, None) @ r
        return state.angular_velocity * np.array([-r[1], r[0]])
    w, v = state.orientation[0], np.asarray(state.orientation[1:])
    r = r + 2.0 * np.cross(v, np.cross(v, r) + w * r)  # the unit quaternion's rotation
    return np.cross(state.angular_velocity, r)
