"""Probes: pressure at a point, free-surface elevation along a vertical line (a wave
gauge), the force on a group of wall particles, the volume flow rate through a
face and the state of a moving or floating body, sampled during a run.

    >>> from taisph.probes import Probes, pressure, elevation, force
    >>> probes = Probes([pressure("P1", at=(3.22, 0.16)), elevation("gauge", at=0.6, every=10),
    ...                  force("floor", walls=floor_ids)], path="out/probes.csv")  # doctest: +SKIP
    >>> sim.run(1.5, writers=[probes])                                           # doctest: +SKIP
    >>> probes.times, probes.values["P1"], probes.values["floor"]                # doctest: +SKIP

Points must lie inside the scene's domain: :func:`check_inside` refuses one outside,
naming the probe, the coordinate and the domain's range, before anything runs; and
outside the walls: :func:`check_placement` refuses a pressure or flow probe inside a wall
or an obstacle, where it would read nothing all run.
A scene file's ``[[probes]]`` are sampled the same way into ``OUT/probes.csv``
(docs/scenes.md), beside it ``OUT/probes.json`` says what each column measures and in
which unit (Pa, m, N, m^2/s or m^3/s, a body's m, rad, m/s, rad/s, N; :func:`read_units`,
docs/probes.md), and ``python -m taisph plot OUT`` draws them, an axis per quantity.
Definitions (V_j = m_j / rho_j, W the scene's kernel and h; sums over fluid particles j
within the kernel support of x):

``pressure`` at x: the Shepard interpolation of the fluid's pressure,

    p(x) = sum_j p_j V_j W(x - x_j) / phi(x),     phi(x) = sum_j V_j W(x - x_j),

where phi, the fluid fraction (1 inside the water, 1/2 on a flat free surface or a
wall face, 1/4 in a corner), is at least ``min_fluid_fraction`` = 0.2; below it the
probe reads no value (NaN; ``nan`` in the CSV): a point more than about h above the
water, or one lone splash particle (which alone gives phi <= 0.27 in 2D, 0.15 in 3D
with the cubic spline and h = 1.3 dx). Wall particles do not enter the sums.
With ``to``, a sensor's face: the mean of p over the points of
:func:`taisph.probes.face_points` (a segment in 2D; a rectangle in a coordinate plane
in 3D), at most dx/2 apart, a dry point (phi below the threshold) counting as 0.

``elevation`` along the vertical line through (x, z): the highest height at which
phi falls through 1/2 going up (phi sampled every dx/2 along the line, across the
domain's height, and interpolated linearly), the level at which a flat free surface
lies (DualSPHysics's water-level gauge uses the same criterion on the kernel sum of
mass, with a threshold of 0.4-0.5 of a particle's mass). A
splash or a lone particle above the surface does not count (phi < 1/2); no water
on the line reads NaN.

``force`` on a wall group: the force of the fluid on those wall particles as the
momentum equation has it, minus the sum over fluid particles f of m_f times the
acceleration each wall particle w of the group gives f through the pressure terms
and the viscous terms (:data:`taisph.probes.device.FORCE_TERMS`: the pressure gradient
with dummy walls, the Lennard-Jones force with those walls, and the laminar or
artificial viscosity where it acts between fluid and walls, ``walls=True``: the
shear force). By Newton's third law these are the
forces the fluid feels from the wall, so in still water the forces on all walls add
up to the water's weight, whatever the walls' discretisation; the alternative, each
wall particle's extrapolated pressure times an area, needs wall normals and areas
and is only right for the first layer of particles of a flat wall (DualSPHysics's
force gauge also sums the SPH accelerations of the boundary particles). In a channel
driven by a body force the probe's shear force on the walls balances the driving
force at steady state (tests/test_probes.py); a drag coefficient is the probe on a
body's wall group divided by 1/2 rho U^2 D.

``body``: the state of a body of the scene (:meth:`taisph.Scene.add_body`) as
``Simulation.bodies()`` reads it after the step: its reference point (centre of mass of
a floating body, pivot of a prescribed one), orientation (2D: angle, rad; 3D: unit
quaternion w, x, y, z), velocity, angular velocity and the force of the fluid (and of
contacts; not gravity) on it in the step, in the columns of :data:`BODY_COLUMNS`
(2D: ``NAME_x, NAME_y, NAME_angle, NAME_vx, NAME_vy, NAME_omega, NAME_fx, NAME_fy``).
No device sums: the body's own record, downloaded.

``flow`` through a face (a segment in 2D, a rectangle in a coordinate plane in 3D):

    Q = sum_k (u(x_k) . n) |face| / K,    u(x) = sum_j v_j V_j W(x - x_j) / phi(x),

over the face's K points (:func:`taisph.probes.face_points`, the middles of equal parts
at most dx/2 a side; a dry point counts as no flow), n its unit normal
(:func:`taisph.probes.flow`): m^2/s per unit depth in 2D, m^3/s in 3D. Near a wall the
fluid-only interpolation leans towards the fluid's velocity a support away (no wall
particle enters the sums): in a channel L/20 wide the flow rate of the Poiseuille
parabola reads within about 1 % (tests/test_probes.py).

Which state: a sample reads the cell-sorted state ``S`` the last step's rates were
computed from, after the step: the one the forces were computed from, with the dummy
walls' extrapolated pressure (the updated state ``C`` has no wall pressure, and its
pressure is not computed until the next step). With the default predictor-corrector
``S`` holds the new positions x^{n+1} and the predicted density (O(dt^2) from the
corrected one); the sample is labelled t^{n+1}. With the Euler-type integrators
``S`` is the state at the start of the step, and the sample is labelled t^n.

Cost: one kernel launch per sample (the sums of all due probes in one parallel
loop) and a download of a few numbers per point; measured in docs/scenes.md.
"""

from .spec import (BODY_COLUMNS, KINDS, MIN_FLUID_FRACTION, InsideWallError, OutsideDomainError, Probe, body,
                   check_bodies, check_inside, check_placement, elevation, face_points, flow, force, outside, parse,
                   pressure)
from .writer import ELEVATION_FRACTION, Probes, read_csv, read_units, surface_height, units_path

__all__ = ["Probe", "Probes", "pressure", "elevation", "force", "read_csv", "read_units", "units_path",
           "surface_height", "KINDS", "ELEVATION_FRACTION", "MIN_FLUID_FRACTION", "check_inside", "outside",
           "OutsideDomainError", "check_placement", "InsideWallError", "face_points", "flow", "body", "check_bodies",
           "BODY_COLUMNS"]
