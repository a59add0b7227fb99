"""Every case parameter has a declared range (taisph.scene.parameters.checked), and a value
outside it, or a combination that cannot be built, is refused with a message that names
the parameter, its value and what is allowed, before anything is built; no library
error (numpy, ZeroDivisionError, MemoryError, ...) reaches the user."""

import inspect
import re

import pytest

import taisph
from taisph.scene.parameters import Flag, Number, OneOf, Optional, ParameterError, Vector, lattice_count

CASES = taisph.cases.CASES


def bad_values(rng):
    """Values just outside a declared range (and of the wrong kind)."""
    if isinstance(rng, Optional):  # None is allowed
        return [v for v in bad_values(rng.inner) if v is not None]
    if isinstance(rng, Number):
        out = [float("nan"), float("inf"), "abc"]
        if rng.low is not None:
            out.append(rng.low if rng.low_open else rng.low - 1)
        if rng.high is not None:
            out.append(rng.high if rng.high_open else rng.high + 1)
        if rng.integer:
            out.append(2.5)
        return out
    if isinstance(rng, OneOf):
        return ["nonsense", None]
    if isinstance(rng, Flag):
        return ["maybe", None]
    if isinstance(rng, Vector):
        return [(1.0,), "abc", tuple(bad_values(c)[0] for c in rng.components)]
    raise AssertionError(f"no bad values for {rng!r}")


OUT_OF_RANGE = [(case, name, value) for case, func in CASES.items() for name, rng in func.ranges.items()
                for value in bad_values(rng)]


def test_every_case_declares_every_parameter():
    """All 20 built-in cases declare a range for each parameter, and each default lies in
    its range (@checked also refuses, at import, a case that does not)."""
    assert len(CASES) == 20
    for case, func in CASES.items():
        params = inspect.signature(func).parameters
        assert list(func.ranges) == list(params), case
        for name, p in params.items():
            assert func.ranges[name].accepts(p.default), (case, name, p.default)


@pytest.mark.parametrize("case,name,value", OUT_OF_RANGE, ids=[f"{c}-{n}={v!r}" for c, n, v in OUT_OF_RANGE])
def test_out_of_range_parameter_is_refused_with_its_range(case, name, value):
    """A value outside the declared range: ParameterError "CASE: NAME must be RANGE, got VALUE"."""
    rng = CASES[case].ranges[name]
    with pytest.raises(ParameterError) as err:
        CASES[case](**{name: value})
    assert str(err.value) == f"{case}: {name} must be {rng.describe()}, got {value!r}"


NONSENSE = (-1.0, 0.0, float("nan"), float("inf"), 1e12, "abc", None)


@pytest.mark.parametrize("case", list(CASES))
def test_no_library_error_leaks(case):
    """Each parameter set to each of -1, 0, NaN, inf, 1e12, 'abc', None: the case either
    builds a scene that passes Scene.validate, or raises ParameterError naming that
    parameter. 1e12 m sizes are refused for memory, 1e12 m spacings for leaving a
    block without particles: nothing is allocated."""
    func = CASES[case]
    for name in func.ranges:
        for value in NONSENSE:
            try:
                scene = func(**{name: value})
            except ParameterError as err:
                assert re.search(rf"\b{name}\b", str(err)), (name, value, str(err))
            else:
                scene.validate()


# What several parameters decide together: (case, parameters, what the message must say)
RELATIONS = [
    ("dam_break", dict(dx=5.0), "dx = 5 m leaves the water column (width = 1 m, height = 2 m) without particles "
                                "along width: dx must be at most 1 m"),
    ("dam_break", dict(width=5.0), "the water column (width = 5 m, height = 2 m) must fit in the tank"),
    ("dam_break", dict(dx=1e-6), "dx = 1e-06 m fills the water column"),
    ("dam_break_3d", dict(dx=0.2, depth=0.1), "without particles along depth: dx must be at most 0.1 m"),
    ("hydrostatic_tank", dict(dx=0.6), "dx must be at most 0.5 m"),
    ("dam_break_wedge", dict(wedge_start=0.5), "the wedge (from wedge_start = 0.5 m to wedge_start + wedge_base = "
                                               "1.5 m) must lie on the floor between the column (width = 1 m)"),
    ("dam_break_wedge", dict(wedge_height=5.0), "wedge_height = 5 m) must fit under tank_height = 4 m"),
    ("drop_on_incline", dict(impact_x=2.0), "impact_x = 2 m must lie over the inclined plane"),
    ("drop_on_incline", dict(radius=0.6), "the drop (radius = 0.6 m around impact_x = 0.5 m) must lie between"),
    ("drop_on_incline", dict(dim=3, depth=0.3), "the sphere (radius = 0.2 m) must fit between the side walls "
                                                "(depth = 0.3 m)"),
    ("drop_on_incline", dict(fall=1.0), "does not fit under tank_height = 2.2 m"),
    ("drop_on_incline", dict(dx=0.3, tank_height=5.0), "dx = 0.3 m leaves the drop (radius = 0.2 m)"),
    ("two_fluids", dict(amplitude=0.6), "amplitude must be below height/4 = 0.5 m"),
    ("two_fluids", dict(tank_height=1.0), "the liquid (height = 2 m) must fit under the walls (tank_height = 1 m)"),
    ("poiseuille", dict(dx=3e-4), "dx = 0.0003 m must divide the channel width L = 0.001 m into a whole number"),
    ("couette", dict(L=1e6), "fills the channel (L = 1e+06 m"),
    ("taylor_green", dict(dx=0.3), "dx = 0.3 m must divide L = 1 m into a whole number of particles, at least 8"),
    ("taylor_green", dict(c0=1.5), "c0 = 1.5 m/s must exceed sqrt(7/2) U = 1.87083 m/s"),
    ("taylor_green", dict(dx=0.125, h_factor=3.0), "the periodic box (L = 1 m) must span 3 kernel supports"),
    ("elliptical_drop", dict(dx=2.0), "dx = 2 m leaves the drop (R = 1 m) without particles along R"),
    ("sod", dict(x0=1.5), "the diaphragm x0 = 1.5 must lie inside the tube, 0 < x0 < length = 1"),
    ("sod", dict(dx=0.1), "dx rho_L / rho_R = 0.8 m leaves the right state (length - x0 = 0.5 m) without particles"),
    ("sod", dict(dx=0.05), "the tube and its mirror image (2 length = 2) must span 3 kernel supports"),
    ("sedov", dict(dx=0.125), "the periodic square (size = 1) must span 3 kernel supports"),
]


@pytest.mark.parametrize("case,params,message", RELATIONS, ids=[f"{c}-{p}" for c, p, _ in RELATIONS])
def test_combinations_that_cannot_be_built_are_refused(case, params, message):
    with pytest.raises(ParameterError) as err:
        CASES[case](**params)
    assert str(err.value).startswith(f"{case}: ")
    assert message in str(err.value)


def test_lattice_count_refuses_what_memory_cannot_hold(monkeypatch):
    """The memory estimate: 300 bytes a particle against the machine's memory (here
    pretended to be 1 MB: 3333 particles fit, 3334 do not)."""
    monkeypatch.setattr("taisph.scene.parameters._memory_bytes", lambda: 1e6)
    assert lattice_count("test", "a block", 1.0, ("a", 3333.0)) == 3333
    with pytest.raises(ParameterError, match=r"test: dx = 1 m fills a block \(a = 3334 m\) with 3.33e\+03 "
                                             r"particles, which need at least 0.001 GB; this machine has 0.001 GB"):
        lattice_count("test", "a block", 1.0, ("a", 3334.0))


def test_one_list_of_names_for_every_vocabulary():
    """Solvers, integrators and kernels are named once (taisph.scene.names): the engine's
    registries, case parameters, the command line, scene files and the seed's words all
    offer exactly these, in this order."""
    from taisph.cli.case import build_parser
    from taisph.engine import integrators, smoothing
    from taisph.formats import scenefile_spec, seed
    from taisph.scene import names
    from taisph.scene.parameters import known_integrator, known_kernel, known_solver

    assert tuple(integrators.INTEGRATORS) == names.INTEGRATORS and tuple(smoothing.KERNELS) == names.KERNELS
    assert (known_solver.choices, known_integrator.choices, known_kernel.choices) == (
        names.SOLVERS, names.INTEGRATORS, names.KERNELS)
    options = {a.dest: a.choices for a in build_parser()._actions}
    assert (tuple(options["solver"]), tuple(options["integrator"]), tuple(options["kernel"])) == (
        names.SOLVERS, names.INTEGRATORS, names.KERNELS)
    assert [scenefile_spec.RANGES[k].choices for k in ("solver", "integrator", "kernel")] == [
        names.SOLVERS, names.INTEGRATORS, names.KERNELS]
    assert set(seed.INTEGRATOR_WORDS.values()) <= set(names.INTEGRATORS) and seed.KERNEL_WORDS == names.KERNELS


def test_command_line_defaults_are_the_simulation_defaults():
    """--max-density-error and --max-out-of-range default to Controls' own values."""
    from taisph.cli.case import build_parser
    from taisph.engine.timestep import Controls

    args = build_parser().parse_args(["dam_break"])
    assert (args.max_density_error, args.max_out_of_range) == (Controls().max_density_error, Controls().max_out_of_range)
