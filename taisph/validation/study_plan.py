"""The work-precision study's plan (:mod:`taisph.validation.accuracy_cost`): per case, the
resolutions, the fixed settings, the baseline and the variations it runs."""

from ..formats.scenefile_spec import DEFAULTS as SCENE_FILE_DEFAULTS

F64, F32 = "f64", "f32"

# The scene-file defaults of the keys dam_break_probes_2d.toml sets (taisph/formats/scenefile_spec.py:
# a spline with h = 1.3 dx, the engine's Courant number 0.25; alpha and delta 0 with the Riemann
# formulation, the file's default, and 0.1 each with the symmetric form)
DEFAULT_KERNEL = {key: SCENE_FILE_DEFAULTS[key] for key in ("kernel", "h_factor")}
DEFAULT_COURANT = {"courant": 0.25}

# Per case: the resolutions (dx), fixed run settings, the baseline and the variations.
# A variation is (label, parameters changed from the baseline, precision).
STUDY = {
    "dam_break": dict(
        levels=[0.1, 0.05, 0.025], quick=[0.1, 0.05], fixed=dict(T_end=3.1),
        base=dict(walls="lj"),
        variants=[
            ("base: LJ walls, spline, pc, f64", {}, F64),
            ("dummy walls (free slip)", dict(walls="dummy"), F64),
            ("dummy walls + wall friction", dict(walls="dummy", wall_friction=True), F64),
            ("delta-SPH 0.1", dict(delta=0.1), F64),
            ("Wendland C2", dict(kernel="wendland"), F64),
            ("Gaussian", dict(kernel="gaussian"), F64),
            ("eulermid, dt/4", dict(integrator="eulermid", dt_factor=0.25), F64),
            ("f32", {}, F32),
            # DFSPH (docs/dfsph.md): the default physics' walls, its non-pressure terms
            ("DFSPH, dummy walls + wall friction", dict(walls="dummy", wall_friction=True, solver="dfsph"), F64),
            ("WCSPH default: dummy walls, friction, delta 0.1", dict(walls="dummy", wall_friction=True, delta=0.1,
                                                                     controls=dict(courant=0.4)), F64),
        ],
    ),
    # the same front against the defaults' front at dx = 0.005 (runs.FINE_FRONT), not the experiments':
    # an error that falls with resolution (issue 26)
    "dam_break_front": dict(
        levels=[0.1, 0.05, 0.025, 0.0125], quick=[0.1, 0.05], fixed=dict(T_end=3.1),
        base={},
        variants=[
            ("defaults: dummy walls, friction, delta 0.1, Courant 0.4", {}, F64),
            ("seed physics: LJ walls, Courant 0.25", dict(seed_physics=True), F64),
            ("Wendland C2, h 2 dx", dict(kernel="wendland", h_factor=2.0), F64),
            ("DFSPH", dict(solver="dfsph"), F64),
            ("defaults in f32", {}, F32),
        ],
    ),
    # the flagship's measure that converges (issue 26): Buchner's P1 in the 2D dam break of
    # cases/dam_break_probes_2d.toml, as shipped and with one choice changed
    "dam_break_pressure": dict(
        levels=[0.03, 0.02, 0.01], quick=[0.03], fixed={},
        base={},
        variants=[
            ("the example: Riemann, Wendland h 2 dx, alpha 0.02, delta 0.1", {}, F64),
            ("symmetric form (seed eqs. 7-8)", dict(overrides={"physics.formulation": "symmetric"}), F64),
            ("DFSPH, CFL 0.5", dict(overrides={"solver": "dfsph"}, controls={"courant": 0.5}), F64),
            ("scene-file defaults: spline h 1.3 dx, Riemann (alpha 0, delta 0), Courant 0.25",
             dict(overrides={**DEFAULT_KERNEL, "physics.alpha": 0.0, "physics.delta": 0.0}, controls=DEFAULT_COURANT),
             F64),
            ("defaults, symmetric form (alpha 0.1, delta 0.1)",
             dict(overrides={**DEFAULT_KERNEL, "physics.formulation": "symmetric", "physics.alpha": 0.1,
                             "physics.delta": 0.1}, controls=DEFAULT_COURANT), F64),
            ("defaults, DFSPH (alpha 0.1)", dict(overrides={**DEFAULT_KERNEL, "solver": "dfsph", "physics.alpha": 0.1},
                                                 controls={"courant": 0.5}), F64),
            ("the example in f32", {}, F32),
        ],
    ),
    "hydrostatic_tank": dict(
        levels=[0.05, 0.025, 0.0125], quick=[0.1, 0.05], fixed=dict(t_end=1.0),
        base=dict(walls="dummy", delta=None),
        variants=[
            ("base: dummy walls, spline, pc, f64", {}, F64),
            ("Lennard-Jones walls", dict(walls="lj"), F64),
            ("delta-SPH 0.1", dict(delta=0.1), F64),
            ("Wendland C2", dict(kernel="wendland"), F64),
            ("Gaussian", dict(kernel="gaussian"), F64),
            ("eulermid, dt/4", dict(integrator="eulermid", dt_factor=0.25), F64),
            ("f32", {}, F32),
            ("DFSPH", dict(solver="dfsph"), F64),
        ],
    ),
    "poiseuille": dict(
        levels=[1e-4, 5e-5, 2.5e-5], quick=[1e-4, 5e-5, 2.5e-5], fixed={},
        base={},
        variants=[
            ("base: spline, pc, f64", {}, F64),
            ("delta-SPH 0.1", dict(delta=0.1), F64),
            ("Wendland C2", dict(kernel="wendland"), F64),
            ("Gaussian", dict(kernel="gaussian"), F64),
            ("eulermid", dict(integrator="eulermid"), F64),
            ("f32", {}, F32),
        ],
    ),
    "couette": dict(
        levels=[1e-4, 5e-5, 2.5e-5], quick=[1e-4, 5e-5], fixed={},
        base={},
        variants=[
            ("base: spline, pc, f64", {}, F64),
            ("delta-SPH 0.1", dict(delta=0.1), F64),
            ("Wendland C2", dict(kernel="wendland"), F64),
            ("Gaussian", dict(kernel="gaussian"), F64),
            ("eulermid", dict(integrator="eulermid"), F64),
            ("f32", {}, F32),
            ("DFSPH", dict(solver="dfsph"), F64),
        ],
    ),
    "taylor_green": dict(
        levels=[1 / 20, 1 / 32, 1 / 50], quick=[1 / 16, 1 / 24], fixed=dict(t_end=2.0),
        base=dict(shifting=True, delta=0.1),
        variants=[
            ("base: shifting, delta 0.1, spline, pc, f64", {}, F64),
            ("no delta-SPH", dict(delta=None), F64),
            ("no shifting", dict(shifting=False), F64),
            ("Wendland C2", dict(kernel="wendland"), F64),
            ("Gaussian", dict(kernel="gaussian"), F64),
            ("eulermid, dt/2", dict(integrator="eulermid", dt_factor=0.5), F64),
            ("f32", {}, F32),
        ],
    ),
    "elliptical_drop": dict(
        levels=[0.1, 0.05, 0.025], quick=[0.1, 0.05], fixed={},
        base={},
        variants=[
            ("base: alpha 0.1, spline, pc, f64", {}, F64),
            ("delta-SPH 0.1", dict(delta=0.1), F64),
            ("XSPH 0.5", dict(xsph=0.5), F64),
            ("Wendland C2", dict(kernel="wendland"), F64),
            ("Gaussian", dict(kernel="gaussian"), F64),
            ("eulermid, dt/2", dict(integrator="eulermid", dt_factor=0.5), F64),
            ("f32", {}, F32),
        ],
    ),
    # the piston wave maker (issue 28, check 4): gauges at 1, 2, 3 m read before the ramp's
    # end has passed them and, with the far end's sponge, with no reflection
    "wave_flume": dict(
        levels=[0.08, 0.04, 0.02], quick=[0.08, 0.04], fixed=dict(length=6.0, absorber=2.5, t_end=8.5),
        base={},
        variants=[
            ("base: H 0.04 m, Wendland h 2 dx, alpha 0.02, delta 0.1, pc, f64", {}, F64),
            ("cubic spline, h 1.3 dx", dict(kernel="spline", h_factor=1.3), F64),
            ("alpha 0.005", dict(alpha=0.005), F64),
        ],
    ),
    # Schaefer & Turek's cylinder, Re 20 (issue 27): dx must divide 0.01 m (D/dx = 10, 20)
    "cylinder": dict(
        levels=[0.01, 0.005], quick=[0.01], fixed=dict(t_end=6.0), base={},
        variants=[("base: summed density, shifting, Wendland h 1.3 dx, pc, f64", {}, F64)],
    ),
}

QUICK_CASES = ("dam_break", "poiseuille")
QUICK_VARIANTS = 2  # the baseline and the first variation
