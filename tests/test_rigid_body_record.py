"""The bodies field's record (taisph.terms.rigid_body_record): the layout checkpoints hold,
and the integrators' rules for rigid bodies."""

import pytest

from taisph.engine import integrators
from taisph.terms import rigid_bodies
from taisph.terms.rigid_body_record import BODY, BODY_COLS, Record

# the offsets the field has always had: a checkpoint reads a body's numbers at these
LAYOUT = {"centre": 0, "velocity": 3, "orientation": 6, "omega": 10, "momentum": 13, "acc_prev": 16,
          "alpha_prev": 19, "acc": 22, "alpha": 25, "mass": 28, "particle_mass": 29, "inv_inertia": 30,
          "free_linear": 39, "free_rotation": 42, "table_offset": 45, "table_dt": 46, "table_length": 47,
          "axis": 48, "force": 51, "torque": 54, "pivot": 57, "motion": 60, "hinged_mass_centre": 61}


def test_the_body_record_keeps_the_checkpoints_layout():
    assert BODY.offsets == LAYOUT
    assert BODY_COLS == BODY.cols == 64 == rigid_bodies.BODY_COLS
    assert (rigid_bodies.CENTRE, rigid_bodies.VELOCITY, rigid_bodies.ORIENTATION, rigid_bodies.OMEGA,
            rigid_bodies.FORCE, rigid_bodies.TORQUE) == (0, 3, 6, 10, 51, 54)
    assert BODY.span("inv_inertia") == slice(30, 39) and BODY.span("centre", 2) == slice(0, 2)


def test_a_record_is_declared_by_names_and_widths():
    r = Record([("a", 2), ("b", 1), ("c", 3)])
    assert (r.a, r.b, r.c, r.cols) == (0, 2, 3, 6)
    with pytest.raises(ValueError, match="declared twice"):
        Record([("a", 1), ("a", 2)])
    with pytest.raises(ValueError, match="shadows"):
        Record([("span", 1)])
    with pytest.raises(ValueError, match="width 0"):
        Record([("a", 0)])


def test_every_integrator_says_where_a_body_turns_from():
    turns = {name: cls.rigid_turn for name, cls in integrators.INTEGRATORS.items()}
    assert turns == {"euler": integrators.TURN_START, "eulermid": integrators.TURN_END,
                     "eulermom": integrators.TURN_END, "pc": integrators.TURN_PREDICTED}
    for cls in set(integrators.INTEGRATORS.values()):
        for method in ("rigid_velocity", "rigid_displacement", "rigid_turn_rate"):
            assert getattr(cls, method).__doc__
