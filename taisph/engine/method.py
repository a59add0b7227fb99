"""A solver's method: what the engine asks of the solver a scene names (``Scene.solver``).

The engine (the assembly, the state, the time step, the guards, the run loop and the
diagnosis) is the same for every solver; what differs is one :class:`Method`, found by
name in the registry (:mod:`.solvers`), each in a folder of its own
(``engine/<solver>/``). A new solver is a new folder with a subclass of :class:`Method`
and one line in the registry.
"""


class Method:
    """The hooks of a solver's method; the defaults are those of a method that adds
    nothing to the engine's (no rows, parameters, controls, fields or host loop of its own).

    What it compiles (:class:`taisph.engine.assembly.Solver`)
        name                  the scene's ``solver`` it runs (:data:`taisph.scene.names.SOLVERS`)
        terms(scene)          the scene's terms compiled into its kernels, in order
        eos(scene)            the equation of state it binds (an object with the interface of
                              :mod:`taisph.eos`)
        integrator(scene)     the name of its integrator (:mod:`.integrators`)
        rows(terms, has_shift)    (vectors, scalars, derived) it stores per particle beyond the
                              terms', the integrator's and the equation of state's
        pressure_derived      is the pressure row derived from the equation of state every step
                              (else the method writes it, and it is carried)
        params                its runtime parameters, (name, width), after the engine's
        parameter_values(scene, controls)   their values
        extra_fields(solver, field, capacity, list_capacity)   fields of a field set beyond
                              :class:`.assembly.Args` (``fields.extra``), or None
        step_kernels(solver, fields, serial_sort)   the launches of one step on `fields`, in
                              order, each called as ``kernel(t_target)``

    Its controls (:mod:`.timestep`)
        Controls              a dataclass of its own controls (fields with their defaults, in
                              order), or None: :class:`taisph.engine.timestep.Controls` has them
                              after the engine's
        ranges                {control: range} of those a user sets by name
                              (:data:`taisph.engine.timestep.SETTABLE`)
        control_defaults(scene)   the defaults of the engine's controls for a scene
                              (``courant``, ``force_factor``; None: the engine's default)
        acoustic              does the time step's signal speed include the sound speed
                              (c + |v|), or is it the flow speed |v| alone?
        viscosity_params      its parameters that hold a kinematic viscosity, for the viscous
                              limit of the time step

    Its guards (:mod:`.guards`)
        compression_only      does the density guard count compression only?
        max_speed(scene)      the speed guard's limit when the ``max_speed`` control is None
                              (m/s; 0: off)

    Its state (:class:`taisph.engine.state.State`)
        list_capacity(scene)  entries per particle of its own per-particle list, without
                              neighbour lists (1: none)
        list_bytes(entries, real_bytes)   memory per particle of that list (0: none)
        initial_values(scene) {row: values} its rows start with

    Its host loop (:class:`taisph.run.simulation.Simulation`)
        stepper(solver, fields, serial_sort)   the step's host-side stepper, for a method that
                              iterates on the host (``Simulation.pressure_solve``), or None. A
                              stepper has ``bind(stats)`` (record into `stats`, None: fresh ones;
                              returns them), ``begin_window()`` (a run starts) and ``stats``,
                              whose ``summary()`` is the run summary's ``pressure_solve`` and
                              whose ``failure`` (a dict) is the report's
        causes(code, sim, report)   its account of a tripped guard's `code` (a name of
                              :data:`taisph.engine.status.CODE_NAMES`, or ``"diverged"`` when
                              no other cause applies) in the diagnosis: a list of causes, or None
                              for the engine's (:mod:`.diagnosis`)
    """

    name = ""
    pressure_derived = True
    params = ()
    Controls = None
    ranges = {}
    acoustic = True
    viscosity_params = ()
    compression_only = False

    def terms(self, scene) -> list:
        raise NotImplementedError

    def eos(self, scene):
        raise NotImplementedError

    def integrator(self, scene) -> str:
        raise NotImplementedError

    def step_kernels(self, solver, fields, serial_sort: bool) -> tuple:
        raise NotImplementedError

    def rows(self, terms, has_shift: bool) -> tuple:
        return [], [], []

    def parameter_values(self, scene, controls) -> dict:
        return {}

    def extra_fields(self, solver, field, capacity: int, list_capacity: int):
        return None

    def control_defaults(self, scene) -> dict:
        return {}

    def max_speed(self, scene) -> float:
        return 0.0

    def list_capacity(self, scene) -> int:
        return 1

    def list_bytes(self, entries: int, real_bytes: int) -> int:
        return 0

    def initial_values(self, scene) -> dict:
        return {}

    def stepper(self, solver, fields, serial_sort: bool):
        return None

    def causes(self, code: str, sim, report) -> list | None:
        return None
