"""The device-side status of a simulation: two small arrays the step kernels update, and
the sizes they work on.

Time, step count and the dt history live on the device, so stepping needs no host
round trip; the host reads them every few steps (:class:`taisph.engine.state.State`).

``status`` (f64, whatever the state's precision: time must not be f32):
"""

# clock and time step (taisph.engine.timestep)
TIME = 0  # simulated time (s)
DT = 1  # this step's dt
MAX_ACC2 = 2  # largest |a|^2 over fluid particles of the last rate evaluation
MAX_SIGNAL = 3  # largest c + |v| over fluid particles of the last rate evaluation
DT_MIN = 4  # smallest, largest and sum of the dt taken (run statistics)
DT_MAX = 5
DT_SUM = 6
STEPS = 7  # steps taken
DT_STABLE_MIN = 8  # smallest stability limit met so far (a fixed dt above it warns)
DT_STABLE = 9  # this step's stability limit
FROZEN = 10  # 1 once a guard tripped: every later step has dt = 0
# neighbour lists (taisph.engine.neighbours): largest squared displacement from the
# positions the lists were built at, this step's rebuild decision, a host request to
# rebuild (state changed from outside), and the number of rebuilds so far
MAX_DISP2 = 11
REBUILD = 12
FORCE_REBUILD = 13
REBUILDS = 14
# 1 when this launch found the clock already at its target: the host launched a batch one
# step longer than needed (it cannot know the adaptive dt ahead), and the launch must do
# nothing at all, or the last state would depend on how the batches fell (timing)
IDLE = 15
# the time the run ends at (taisph.Simulation.run; infinite for Simulation.step): the only
# time a step is shortened to land on. Output times are not: a launch reaching one goes
# idle instead (IDLE), so that how often a run is looked at cannot change its trajectory
END_TIME = 16
STATUS_SIZE = 17  # the engine's own; a configuration's terms get theirs after (slots())

# ``flags`` (i32): guard failures (taisph.engine.guards) and removed particles
CODES = 0  # OR of the failure bits below
COUNT = 1  # particles that tripped a guard
REMOVED_COUNT = 2  # particles removed with remove_escaped (left the domain, or density out of range)
RECORDS = 3  # (id, code) pairs of the first MAX_RECORDED offending particles from here
MAX_RECORDED = 16
# of those, removed because their density left the range (taisph.engine.guards)
OUT_OF_RANGE_COUNT = RECORDS + 2 * MAX_RECORDED
# for terms that create particles (Term.creates_particles): the id the next particle
# created gets, and how many could not be created for lack of room in the fields (the
# host grows them ahead of need)
NEXT_ID = OUT_OF_RANGE_COUNT + 1
NO_ROOM = NEXT_ID + 1
FLAGS_SIZE = NO_ROOM + 1  # the engine's own; the terms' follow (slots())

NONFINITE, DENSITY, ESCAPED = 1, 2, 4
# an implicit method's pressure solve reached its maximum iterations unconverged; a particle
# had more neighbours than a method's per-step pair list holds (taisph.engine.method)
UNCONVERGED, CROWDED = 8, 16
# a particle faster than the max_speed control (taisph.engine.guards); the clock stood still
# (set by the host: the step collapsed to zero, taisph.run.simulation)
SPEED, STALLED = 32, 64
CODE_NAMES = {NONFINITE: "non-finite state", DENSITY: "density error", ESCAPED: "left the domain",
              UNCONVERGED: "pressure solve did not converge", CROWDED: "neighbour list full",
              SPEED: "speed above max_speed", STALLED: "time step collapsed"}

# ``sizes`` (i32): the grid's shape and the counts a launch works on (written by the host,
# :meth:`taisph.engine.state.State.setup_grid`)
GRID_SHAPE = 0  # cells along axis d at GRID_SHAPE + d (1 beyond the dimension)
N_CELLS = 3  # cells of the grid
N_PARTICLES = 4  # particles in use (the fields have room for more)
LIST_CAPACITY = 5  # entries per particle's neighbour list (or the method's own list: Method.list_capacity)
SIZES_SIZE = 6


def slots(terms, declared: str, start: int):
    """Slots of the terms' own in a status array, after the engine's `start` ones:
    ``(size, {term name: {slot name: index}})`` for each term's ``declared`` attribute
    (``status_slots`` or ``flag_slots``: ``{name: count}``), in the terms' order."""
    index, where = start, {}
    for term in terms:
        for name, count in getattr(term, declared).items():
            where.setdefault(term.name, {})[name] = index
            index += count
    return index, where
