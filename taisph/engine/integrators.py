"""Time integrators: the seed's ``euler``, ``eulermid`` (alias ``eulermom``) and ``pc``.

Each step of every integrator evaluates the rates (accelerations, d rho/dt, ...) once.
The step is split in two places so that it fuses into the solver's two passes:

``predict``   runs while particles are gathered into cell order, before the rates;
``update``    runs right after the rates of a particle are summed.

Integrated quantities: position (from velocity), velocity (from ``rates.acc``) and
every scalar a term declares in ``integrates`` (density from ``d_density``, ...).
Wall particles are never integrated by these formulas: they move rigidly with their
own prescribed velocity (zero for fixed walls).

If a term provides ``rates.shift`` (XSPH), positions move with ``v + shift`` instead
of ``v``: the shift changes where particles go, not their momentum.

A body that moves as one (a term's solid, e.g. a floating box) advances by its fluid's
integrator's own rule, given by each class's ``rigid_*`` methods (f64, after the force
pass, once per body): ``rigid_velocity`` for the velocity (2D: the angular velocity too; 3D: the angular
momentum), ``rigid_displacement`` for the position (2D: the angle too), and for the
orientation ``rigid_turn`` (where it is advanced from: :data:`TURN_START`,
:data:`TURN_END` or :data:`TURN_PREDICTED`) and ``rigid_turn_rate`` (3D: the rate it turns
by over dt). The same rule for fluid and bodies keeps their total momentum to round-off.
"""


import taichi as ti

from ..scene.names import INTEGRATORS as NAMES  # the one list of the names (checked below)

# where a solid body's orientation is advanced from (an integrator's ``rigid_turn``)
TURN_START = "start"  # after the force pass, from the step's start rate
TURN_END = "end"  # after the force pass, from the step's end rate
TURN_PREDICTED = "predicted"  # by the predictor, before the torque is summed (its lever arms at the step's end)


@ti.data_oriented
class Euler:
    """Forward Euler (seed ``euler``), first order:

        x^{n+1} = x^n + dt v^n,   v^{n+1} = v^n + dt a^n,   q^{n+1} = q^n + dt (dq/dt)^n.
    """

    name = "euler"
    order = 1
    rigid_turn = TURN_START

    def __init__(self, integrated, has_shift=False):
        self.integrated = tuple(integrated)  # ((quantity, rate), ...)
        self.has_shift = has_shift

    def quantities(self):
        return (), ()

    @ti.func
    def _moving(self, v, rates: ti.template()):
        """The velocity positions move with: v, or v + the XSPH shift."""
        u = v
        if ti.static(self.has_shift):
            u = v + rates.shift
        return u

    def bind(self, layout):
        self.q = layout.q
        # (row of the quantity, index of its rate in rates.d)
        self.rows = tuple((getattr(layout.q, qn), k) for k, (qn, _) in enumerate(self.integrated))
        return self

    @ti.func
    def predicted_position(self, s: ti.template(), i, dt):
        return s.Cv[self.q.position, i]

    @ti.func
    def predict(self, s: ti.template(), i, slot, dt):
        pass

    @ti.func
    def advance_wall(self, s: ti.template(), i, dt):
        """Walls move rigidly with their prescribed velocity."""
        s.Cv[self.q.position, i] = s.Sv[self.q.position, i] + dt * s.Sv[self.q.velocity, i]

    @ti.func
    def update(self, s: ti.template(), i, rates: ti.template(), dt):
        q = ti.static(self.q)
        v = s.Sv[q.velocity, i]
        s.Cv[q.position, i] = s.Sv[q.position, i] + dt * self._moving(v, rates)
        s.Cv[q.velocity, i] = v + dt * rates.acc
        for k in ti.static(self.rows):
            s.Cs[k[0], i] = s.Ss[k[0], i] + dt * rates.d[k[1]]

    # --- bodies that move as one (see the module docstring) ------------------------------
    @ti.func
    def rigid_velocity(self, v0, a0, a, dt):
        """A solid body's velocity at the step's end, v1 = v0 + dt a, from its velocity v0
        and its acceleration a of this step (a0: the last step's, unused here). 2D: the
        angular velocity from the angular acceleration; 3D: the angular momentum from the
        torque."""
        return v0 + dt * a

    @ti.func
    def rigid_displacement(self, v0, v1, a0, dt):
        """A solid body's displacement over the step, dx = dt v0 (v0, v1: its velocity at
        the step's start and end; a0: the last step's acceleration). 2D: the angle's
        change from the angular velocity."""
        return dt * v0

    @ti.func
    def rigid_turn_rate(self, w0, w1, alpha0, dt):
        """The angular velocity a 3D body's orientation turns by over dt: w0, the step's
        start rate (w1: its end rate; alpha0: the last step's angular acceleration)."""
        return w0


@ti.data_oriented
class EulerMid(Euler):
    """Semi-implicit (symplectic) Euler, the seed's ``eulermid``/``eulermom``:
    positions are advanced with the already updated velocity,

        v^{n+1} = v^n + dt a^n,   x^{n+1} = x^n + dt v^{n+1},   q^{n+1} = q^n + dt (dq/dt)^n.
    """

    name = "eulermid"
    rigid_turn = TURN_END

    @ti.func
    def update(self, s: ti.template(), i, rates: ti.template(), dt):
        q = ti.static(self.q)
        v = s.Sv[q.velocity, i] + dt * rates.acc
        s.Cv[q.position, i] = s.Sv[q.position, i] + dt * self._moving(v, rates)
        s.Cv[q.velocity, i] = v
        for k in ti.static(self.rows):
            s.Cs[k[0], i] = s.Ss[k[0], i] + dt * rates.d[k[1]]

    @ti.func
    def rigid_displacement(self, v0, v1, a0, dt):
        """dx = dt v1, with the velocity already updated (2D: the angle from the updated
        angular velocity)."""
        return dt * v1

    @ti.func
    def rigid_turn_rate(self, w0, w1, alpha0, dt):
        """w1: a 3D body turns by its updated rate (omega from the updated angular momentum
        in the orientation of the step's start)."""
        return w1


@ti.data_oriented
class PredictorCorrector(Euler):
    """Predictor-corrector after Price (2004, PhD thesis, sec. 2.5.1), the seed's ``pc``.

    Predictor (using the rates of the previous step, stored per particle):

        x^{n+1} = x^n + dt v^n + dt^2/2 a^n,   v* = v^n + dt a^n,   q* = q^n + dt (dq/dt)^n

    then the rates a^{n+1}, (dq/dt)^{n+1} are evaluated at (x^{n+1}, v*, q*) and the
    corrector gives

        v^{n+1} = v* + dt/2 (a^{n+1} - a^n),   q^{n+1} = q* + dt/2 ((dq/dt)^{n+1} - (dq/dt)^n).

    Second order; one rate evaluation per step (for positions it is velocity Verlet).
    The predictor runs for wall particles too: their stored rates are always zero,
    so it moves them rigidly with their own velocity.
    The rates are bootstrapped by a zero-length step when the simulation starts.
    """

    name = "pc"
    order = 2
    rigid_turn = TURN_PREDICTED

    def quantities(self):
        vectors = ("acc_prev", "shift_prev") if self.has_shift else ("acc_prev",)
        return vectors, tuple(rate + "_prev" for _, rate in self.integrated)

    def bind(self, layout):
        super().bind(layout)
        self.prev_rows = tuple(getattr(layout.q, rate + "_prev") for _, rate in self.integrated)
        return self

    @ti.func
    def predicted_position(self, s: ti.template(), i, dt):
        q = ti.static(self.q)
        v = s.Cv[q.velocity, i]
        if ti.static(self.has_shift):
            v += s.Cv[q.shift_prev, i]
        return s.Cv[q.position, i] + dt * v + (0.5 * dt * dt) * s.Cv[q.acc_prev, i]

    @ti.func
    def predict(self, s: ti.template(), i, slot, dt):
        q = ti.static(self.q)
        s.Sv[q.position, slot] = self.predicted_position(s, i, dt)
        s.Sv[q.velocity, slot] = s.Cv[q.velocity, i] + dt * s.Cv[q.acc_prev, i]
        for k in ti.static(range(len(self.rows))):
            s.Ss[self.rows[k][0], slot] = s.Cs[self.rows[k][0], i] + dt * s.Cs[self.prev_rows[k], i]

    @ti.func
    def advance_wall(self, s: ti.template(), i, dt):
        pass  # the predictor already moved it (wall rates stay zero)

    @ti.func
    def update(self, s: ti.template(), i, rates: ti.template(), dt):
        q = ti.static(self.q)
        half = 0.5 * dt
        s.Cv[q.position, i] = s.Sv[q.position, i]
        s.Cv[q.velocity, i] = s.Sv[q.velocity, i] + half * (rates.acc - s.Sv[q.acc_prev, i])
        s.Cv[q.acc_prev, i] = rates.acc
        if ti.static(self.has_shift):
            s.Cv[q.shift_prev, i] = rates.shift
        for k in ti.static(range(len(self.rows))):
            row = self.rows[k][0]
            new_rate = rates.d[self.rows[k][1]]
            s.Cs[row, i] = s.Ss[row, i] + half * (new_rate - s.Ss[self.prev_rows[k], i])
            s.Cs[self.prev_rows[k], i] = new_rate

    @ti.func
    def rigid_velocity(self, v0, a0, a, dt):
        """The trapezoid v1 = v0 + dt/2 (a0 + a), a0 the last step's acceleration (2D:
        angular velocity; 3D: angular momentum from the last and this step's torques)."""
        return v0 + 0.5 * dt * (a0 + a)

    @ti.func
    def rigid_displacement(self, v0, v1, a0, dt):
        """Velocity Verlet's dx = dt v0 + dt^2/2 a0 (the predictor's x^{n+1}). 2D: the
        angle's change, which the predictor makes before the torque is summed."""
        return dt * v0 + 0.5 * dt * dt * a0

    @ti.func
    def rigid_turn_rate(self, w0, w1, alpha0, dt):
        """w0 + dt/2 alpha0: the step's mean rate by the last step's angular acceleration,
        which the predictor turns a 3D body by before the torque is summed."""
        return w0 + 0.5 * dt * alpha0


INTEGRATORS = {"euler": Euler, "eulermid": EulerMid, "eulermom": EulerMid, "pc": PredictorCorrector}
if tuple(INTEGRATORS) != NAMES:  # taisph/scene/names.py, in the same order
    raise ImportError(f"engine integrators {tuple(INTEGRATORS)} differ from taisph.scene.names.INTEGRATORS")


def make(name: str, integrated, has_shift=False):
    try:
        cls = INTEGRATORS[name]
    except KeyError:
        raise ValueError(
            f"unknown integrator {name!r}; choose one of euler, eulermid (alias eulermom), pc"
        ) from None
    return cls(integrated, has_shift)
