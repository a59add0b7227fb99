"""The ``bodies`` field's layout: one record of :data:`BODY_COLS` f64 numbers per body,
declared once by name and width (:data:`BODY`), then the prescribed bodies' motion tables.

The offsets follow from the widths in the order declared, so a record may grow only at its
end: the field is state (kept in checkpoints), and a checkpoint reads its numbers at these
offsets. ``tests/test_rigid_body_record.py`` checks every offset and the total.
"""


class Record:
    """Named slots of a flat record, from an ordered list of ``(name, width)``: each name is
    an attribute holding its offset (the sum of the widths before it), ``cols`` the total.

        BODY = Record([("centre", 3), ("velocity", 3)])  ->  BODY.centre == 0, BODY.velocity == 3, BODY.cols == 6
    """

    def __init__(self, slots):
        self.slots = tuple((name, int(width)) for name, width in slots)
        self.offsets, self.widths = {}, {}
        offset = 0
        for name, width in self.slots:
            if name in self.offsets or hasattr(type(self), name):
                raise ValueError(f"record slot {name!r}: declared twice or shadows the record's own attribute")
            if width < 1:
                raise ValueError(f"record slot {name!r}: width {width}, must be at least 1")
            self.offsets[name], self.widths[name] = offset, width
            setattr(self, name, offset)
            offset += width
        self.cols = offset

    def span(self, name: str, n: int | None = None) -> slice:
        """The slice of the slot `name` in a record (its first `n` numbers; default: all)."""
        return slice(self.offsets[name], self.offsets[name] + (self.widths[name] if n is None else n))

    def __repr__(self):
        return f"Record({', '.join(f'{name}@{self.offsets[name]}:{w}' for name, w in self.slots)}; cols {self.cols})"


# A body's record. Vectors have 3 slots in 2D too (2D: x, y used; an angular quantity about z
# in its third slot, the orientation's angle in its first).
BODY = Record([
    ("centre", 3),  # reference point: centre of mass (floating), pivot + offset (prescribed), hinge
    ("velocity", 3),  # of the reference point
    ("orientation", 4),  # 2D: angle (rad); 3D: unit quaternion (w, x, y, z)
    ("omega", 3),  # angular velocity, world frame (2D: about z)
    ("momentum", 3),  # 3D: angular momentum L, world frame
    ("acc_prev", 3),  # the last step's acceleration (the predictor-corrector's a^n)
    ("alpha_prev", 3),  # 2D: the last step's angular acceleration; 3D: the last step's torque
    ("acc", 3),  # acceleration of the reference point (the walls' pressure)
    ("alpha", 3),  # angular acceleration
    ("mass", 1),
    ("particle_mass", 1),  # mass / particles (contact)
    ("inv_inertia", 9),  # body-frame inverse inertia, row-major (2D: the first only)
    ("free_linear", 3),  # 1 free, 0 fixed, per world axis
    ("free_rotation", 3),  # the same for rotation (2D: all three the same)
    ("table_offset", 1),  # prescribed: where its table starts in the field
    ("table_dt", 1),  # prescribed: its table's time step
    ("table_length", 1),  # prescribed: its table's rows
    ("axis", 3),  # prescribed, 3D: rotation axis
    ("force", 3),  # the last step's fluid + contact force (probes; gravity not included)
    ("torque", 3),  # the same for torque (2D: about z)
    ("pivot", 3),  # prescribed: the reference its table's offset is added to
    ("motion", 1),  # MOTIONS code
    ("hinged_mass_centre", 3),  # hinged: centre of mass from the hinge, body frame (else 0)
])
BODY_COLS = BODY.cols  # 64
CAPACITY = 1 << 18  # numbers in the field: every record, then the tables
MOTIONS = {"prescribed": 1, "floating": 2}  # codes of the ``motion`` slot


def bodies_of(s):
    """The ``bodies`` field of the state `s` (compile time: ``ti.static(bodies_of(s))``): the one
    place the device code names it."""
    return s.store.bodies
