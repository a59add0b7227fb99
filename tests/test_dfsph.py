"""DFSPH (``Scene(solver="dfsph")``, taisph/engine/dfsph/solver.py): the implicit incompressible
solver against physics, its failures, and its place in the command line and scene
files. The long validations (dx as in the issue) are marked slow; docs/dfsph.md
gives their measured values."""

import math

import numpy as np
import pytest

import taisph
from taisph.cli import case as cli_case
from taisph.cli import main as cli
from taisph.engine.dfsph import solver as dfsph
from taisph.engine.dfsph import pairs
from taisph.validation import runs


def dfsph_scene(case="dam_break", **params):
    scene = getattr(taisph.cases, case)(**params)
    scene.solver = "dfsph"
    return scene


def ko_scales(scene):
    """L, the dam break's column width, and sqrt(2 g/L): Koshizuka & Oka's Z = x/L and
    T = t sqrt(2 g/L)."""
    L = float(scene.position[scene.kind == taisph.FLUID, 0].max() + scene.dx / 2)
    return L, math.sqrt(2 * -scene.terms_by_name["gravity"].values["gravity"][1] / L)


def mean_compression(sim):
    """DFSPH's error measure: the mean over fluid of max(rho/rho0 - 1, 0)."""
    rho = sim.density()[sim.fluid]
    return float(np.mean(np.maximum(rho / sim.scene.materials[0].rho0 - 1.0, 0.0)))


def test_still_water_keeps_its_hydrostatic_pressure_quick():
    """A 1 m x 0.5 m tank at dx = 0.05 for 1 s: rms(p - rho g (H - y)) over the second half
    below 0.3 % of rho g H (measured 0.103 %; the slow test holds 0.075 % at dx = 0.0125),
    water still (max |v| over the last quarter below 0.5 % of sqrt(g H); measured 0.160 %),
    no particle through a wall."""
    out = runs.run("hydrostatic_tank", dx=0.05, solver="dfsph", t_end=1.0, samples=4)
    assert not out.diverged
    assert out.error < 0.003, out.metrics
    assert out.metrics["vmax_last_quarter"] < 0.005, out.metrics
    assert out.metrics["particles_outside"] == 0


@pytest.mark.slow
def test_still_water_keeps_its_hydrostatic_pressure():
    """Issue 14 asked for 1 %: rms pressure error over the second half <= 0.075 % of rho g H
    (dx = 0.0125, 2 s; measured 0.0237 %, 14 s on 2 cores; 0.93 % before the pressure
    force's lattice scale and the pairing repulsion)."""
    out = runs.run("hydrostatic_tank", dx=0.0125, solver="dfsph", t_end=2.0, samples=10)
    assert out.error <= 0.00075, out.metrics
    assert out.metrics["particles_outside"] == 0


def test_dam_break_stays_incompressible_and_runs_quick():
    """dx = 0.04, stepped to each of Koshizuka & Oka's times after the release up to
    T = t sqrt(2 g/L) = 3.1 (t = 0.70 s; L = 1 m, the column's width): the surge front
    Z = (max x + dx/2)/L has a mean |Z - Z_KO| over those 8 points of at most 0.20
    (measured 0.161; the slow test's bar at dx = 0.02, where it measures 0.193, and about the
    model's own distance from the experiment, 0.215 at dx = 0.005, so no tighter); the mean
    compression at those times is at most 0.06 % (measured 0.0196 % at worst); the last
    stretch's solves met their 0.02 % tolerance with 2-20 iterations on average (5.2)."""
    ko, _ = runs.reference("koshizuka_oka_1996_surge_front_pysph.csv")
    scene = dfsph_scene(dx=0.04)
    L, scale_T = ko_scales(scene)
    sim = taisph.Simulation(scene)
    compression, dz = [], []
    for T, Z in ko[ko[:, 0] > 0]:
        summary = sim.run(T / scale_T, frames=1)
        compression.append(mean_compression(sim))
        dz.append((sim.positions()[sim.fluid][:, 0].max() + scene.dx / 2) / L - Z)
    print(f"mean |Z - Z_KO| {np.mean(np.abs(dz)):.3f}, worst compression {max(compression):.4%}")
    assert len(dz) == 8 and np.mean(np.abs(dz)) <= 0.20, dz
    assert max(compression) <= 0.0006, compression
    stats = summary.pressure_solve
    assert stats["density_error_max"] <= sim.controls.dfsph_tolerance
    assert 2 <= stats["density_iterations_mean"] < 20
    assert "DFSPH iterations per step: density" in str(summary)


@pytest.mark.slow
def test_dam_break_front_and_compression_against_koshizuka_oka():
    """Issue 14: at dx = 0.02 the surge front's mean |Z - Z_KO| (T <= 3.1) <= 0.20
    (measured 0.193; WCSPH's default 0.151), and the mean compression at most 0.03 % in
    every frame, 0.05 s apart to 1 s (measured at most 0.0095 %; issue 14 asked for 0.5 %)."""
    out = runs.run("dam_break", dx=0.02, solver="dfsph", T_end=3.1)
    assert out.error <= 0.20, out.metrics
    sim = taisph.Simulation(dfsph_scene(dx=0.02))
    worst = 0.0
    for k in range(1, 21):
        sim.run(0.05 * k, frames=1)
        worst = max(worst, mean_compression(sim))
    print(f"front {out.error:.3f}, worst frame's mean compression {worst:.4%}")
    assert worst <= 0.0003


def test_a_solve_that_does_not_converge_stops_the_run_and_says_why(tmp_path):
    """Beyond dfsph_error_bound times its tolerance (0.37 % after 3 iterations, > 10 x 0.02 %)
    a solve stops the run; the remedy names what the user can set, as typed on the command
    line and in Python."""
    sim = taisph.Simulation(dfsph_scene(dx=0.04), dfsph_max_iterations=3, dfsph_retries=0)
    with pytest.raises(taisph.run.simulation.SimulationError) as err:
        sim.run(0.3, out=tmp_path)
    message = str(err.value)
    assert "pressure solve did not converge" in message
    assert "solve reached 3 iterations" in message and "tolerance 0.02 %, kept up to 10 times that" in message
    for option in ("--dt-max ", "--courant ", "--force-factor ", "--dfsph-max-iterations 6"):
        assert option in message, option  # the remedy, as typed on the command line
    assert "Simulation(scene, dt_max=" in message and "dfsph_max_iterations=6)" in message
    parser = cli_case.build_parser("dam_break")
    for word in message.split():
        if word.startswith("--"):
            assert any(word in a.option_strings for a in parser._actions), word  # every option exists
    assert err.value.report["pressure_solve"]["iterations"] == 3
    assert any(f.name.endswith("_last_good.vtu") for f in err.value.files)


def test_a_solve_that_ends_within_the_bound_is_kept_and_counted(tmp_path):
    """Issue 25 (2): with 12 iterations at most, 4 of the dam break's steps (dx = 0.04, to
    0.3 s) end above the 0.02 % tolerance, the worst at 6.7 times it (measured with the
    Chebyshev-accelerated solve; 20 iterations were needed for the same with plain Jacobi):
    within the bound of 10 the run goes on and its summary says how many and how far; with a
    bound of 5 (and no retries) and 10 iterations it stops."""
    summary = taisph.Simulation(dfsph_scene(dx=0.04), dfsph_max_iterations=12).run(0.3, frames=1)
    ps = summary.pressure_solve
    assert summary.sim_time == pytest.approx(0.3)
    assert 1 <= ps["steps_above_tolerance"] < summary.steps
    assert 1 < ps["worst_over_tolerance"] <= 10
    assert ps["density_error_max"] == pytest.approx(ps["worst_over_tolerance"] * 0.0002)
    assert f"{ps['steps_above_tolerance']} steps kept with a solve above its tolerance (worst" in str(summary)
    # 10 iterations: with frames (other step sizes) some solve ends beyond 5 times the tolerance
    sim = taisph.Simulation(dfsph_scene(dx=0.04), dfsph_max_iterations=10, dfsph_error_bound=5, dfsph_retries=0)
    with pytest.raises(taisph.run.simulation.SimulationError) as err:
        sim.run(0.3, out=tmp_path)
    assert "kept up to 5 times that" in str(err.value)
    assert err.value.report["pressure_solve"]["error"] > 5 * 0.0002
    converged = taisph.Simulation(dfsph_scene(dx=0.1)).run(0.05, frames=1)
    assert converged.pressure_solve["steps_above_tolerance"] == 0
    assert "above its tolerance" not in str(converged)


CONTROL_VALUES = dict(dt_max=0.001, force_factor=0.05, dfsph_tolerance=0.0005, dfsph_divergence_tolerance=0.002,
                      dfsph_min_iterations=3, dfsph_max_iterations=600, dfsph_error_bound=4.0, dfsph_retries=5,
                      max_speed=40.0)


def test_every_dfsph_control_is_an_option_that_reaches_the_simulation(monkeypatch):
    """Issue 25 (1): --dt-max, --force-factor, --dfsph-tolerance ... parse (with their ranges)
    and reach Simulation's controls; each is one of the settable controls, with its default."""
    from taisph.engine.timestep import SETTABLE, Controls

    assert set(CONTROL_VALUES) == set(SETTABLE)
    argv = ["dam_break", "--solver", "dfsph", "--no-output", "--no-progress"]
    for name, value in CONTROL_VALUES.items():
        argv += ["--" + name.replace("_", "-"), str(value)]
    args = cli_case.build_parser("dam_break").parse_args(argv)
    assert {name: getattr(args, name) for name in CONTROL_VALUES} == CONTROL_VALUES
    seen = {}

    class Stop(Exception):
        pass

    def fake(scene, **kwargs):
        seen.update(kwargs)
        seen["controls"] = taisph.engine.timestep.controls_for(scene, **{k: v for k, v in kwargs.items()
                                                                         if k not in ("arch", "precision", "threads")})
        raise Stop

    monkeypatch.setattr(taisph, "Simulation", fake)
    with pytest.raises(Stop):
        cli_case.run_case("dam_break", argv[1:])
    for name, value in CONTROL_VALUES.items():
        assert getattr(seen["controls"], name) == value, name
    with pytest.raises(cli_case.UsageError, match="--dfsph-max-iterations: must be an integer"):
        cli_case.build_parser("dam_break").parse_args(["dam_break", "--dfsph-max-iterations", "0"])
    with pytest.raises(cli_case.UsageError, match="--dfsph-error-bound: must be >= 1"):
        cli_case.build_parser("dam_break").parse_args(["dam_break", "--dfsph-error-bound", "0.5"])
    assert "default 300" in cli_case.build_parser("dam_break").format_help().replace("\n", " ")
    assert Controls.dfsph_max_iterations == 300
    sim = taisph.engine.timestep.controls_for(dfsph_scene(dx=0.1), **CONTROL_VALUES)  # and from Python
    assert all(getattr(sim, k) == v for k, v in CONTROL_VALUES.items())


def test_a_scene_file_sets_the_dfsph_controls(tmp_path, capsys, monkeypatch):
    """The controls are top-level keys of a scene file, of the same names; checked with the
    command line's ranges; the command line's options override them."""
    from taisph.formats.scenefile import load
    from taisph.formats.scenefile_spec import SceneFileError
    from taisph.scene.catalogue import find_scene_file

    text = find_scene_file("dam_break_probes_2d.toml").read_text()
    path = tmp_path / "scene.toml"
    path.write_text("\n".join(f"{k} = {v}" for k, v in CONTROL_VALUES.items()) + "\n" + text)
    scene, settings = load(path, {"solver": "dfsph", "dx": 0.1})
    assert settings.controls == CONTROL_VALUES
    sim = taisph.Simulation(scene, **settings.controls)
    assert all(getattr(sim.controls, k) == v for k, v in CONTROL_VALUES.items())
    sim.close()
    with pytest.raises(SceneFileError, match="dfsph_max_iterations = 0: must be an integer"):
        load(path, {"dfsph_max_iterations": 0})
    seen = {}
    real = taisph.Simulation

    def spy(scene, **kwargs):
        seen.update(kwargs)
        return real(scene, **kwargs)

    monkeypatch.setattr(taisph, "Simulation", spy)
    assert cli.main([str(path), "--solver", "dfsph", "--dx", "0.1", "--t-end", "0.01", "--frames", "1", "--no-output",
                     "--no-progress", "--dt-max", "0.002"]) == 0
    assert seen["dt_max"] == 0.002 and seen["dfsph_tolerance"] == CONTROL_VALUES["dfsph_tolerance"]
    assert "dt min/mean/max" in capsys.readouterr().out


def test_guards_still_work_with_dfsph():
    """A wall sampled at dx/12 overflows the pair list: the guard says so (the density guard
    trips too: such a wall crushes the fluid in the sums)."""
    scene = taisph.Scene("crowded", dim=2, dx=0.05, smoothing_length=0.065, domain=([0, 0], [1, 1]),
                         terms=[taisph.terms.Gravity()], solver="dfsph")
    scene.add_fluid(np.stack(np.meshgrid(np.arange(0.3, 0.7, 0.05), np.arange(0.1, 0.5, 0.05)), -1).reshape(-1, 2))
    scene.add_walls(np.stack([np.arange(0.0, 1.0, 0.004), np.full(250, 0.05)], -1))
    sim = taisph.Simulation(scene)
    with pytest.raises(taisph.run.simulation.SimulationError, match="neighbour list full"):
        sim.run(0.5)


def test_scenes_dfsph_cannot_run_are_refused():
    scene = taisph.cases.dam_break(dx=0.2, seed_physics=True)  # Lennard-Jones walls
    scene.solver = "dfsph"
    with pytest.raises(ValueError, match="lennard_jones_wall.*cannot be used with solver='dfsph'"):
        scene.validate()
    scene = taisph.cases.dam_break(dx=0.2)
    scene.solver = "isph"
    with pytest.raises(ValueError, match="unknown solver 'isph'"):
        scene.validate()


def test_memory_and_pair_list_capacity():
    sim = taisph.Simulation(dfsph_scene(dx=0.1))
    k = pairs.capacity(sim.scene)
    assert k == 32  # 2D, h = 1.3 dx: 20 neighbours on the lattice, 21.2 in a disc
    # 6 vectors, 9 scalars (kappa_prev: the Chebyshev iteration), 3 integers (current, sorted, last good),
    # cell, list count and entries
    assert sim.bytes_per_particle() == 3 * (6 * 16 + 9 * 8 + 3 * 4) + 4 + 4 + 32 * 12 == 932


def test_the_rest_density_is_the_lattice_s():
    """The solve's rest ratio is sum_j dx^2 W(x_i - x_j) over a square lattice, computed here
    independently with Monaghan's 2D cubic spline (sigma = 10 / (7 pi h^2), support 2h,
    h = 1.3 dx), to 1e-12."""
    scene = dfsph_scene(dx=0.1)
    h, dx = scene.smoothing_length, scene.dx
    assert h == pytest.approx(1.3 * dx)
    n = np.arange(-3, 4)
    q = np.hypot(*np.meshgrid(n, n)).ravel() * dx / h
    w = np.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0))
    expected = 10 / (7 * math.pi * h**2) * w.sum() * dx**2
    assert dfsph.lattice_ratio(scene) == pytest.approx(expected, rel=1e-12)
    assert abs(expected - 1) < 1e-4  # the spline's lattice sum is 0.99995, not 1


def test_command_line_solver_option(capsys):
    for args in (["--solver", "dfsph"], ["--set", "solver=dfsph"]):
        assert cli.main(["dam_break", "--dx", "0.1", "--t-end", "0.05", "--frames", "1", "--no-output",
                         "--no-progress", *args]) == 0
        out = capsys.readouterr().out
        assert "solver dfsph" in out and "DFSPH pressure (in place of continuity" in out
        assert "DFSPH iterations per step" in out
    assert cli.main(["dam_break", "--dx", "0.1", "--t-end", "0.01", "--frames", "1", "--no-output",
                     "--no-progress"]) == 0
    assert "solver wcsph" in capsys.readouterr().out
    assert cli.main(["dam_break", "--set", "solver=isph", "--no-output"]) == 2
    assert "solver must be one of wcsph, dfsph" in capsys.readouterr().err


COUETTE_BAR = 0.008  # max |u - u_exact| / V0 at t = 0.1125 s: about 3x what dx = 1e-4 measures


def test_a_moving_wall_drives_the_fluid_couette():
    """Couette start-up under DFSPH (laminar viscosity, no-slip walls) at dx = 1e-4 (L/10):
    max |u - u_exact| / V0 at t = 0.1125 s below 0.8 % (measured 0.26 %; 1.04 % at
    t = 0.0225 s, not asserted). Refining does not bring it nearer: at dx = 5e-5 it is 8.8 %
    (the strict xfail below; docs/dfsph.md, "What accuracy costs")."""
    out = runs.run("couette", dx=1e-4, solver="dfsph", times=(0.0225, 0.1125))
    assert not out.diverged
    assert out.metrics["linf_t0.1125"] < COUETTE_BAR, out.metrics


@pytest.mark.xfail(strict=True, reason="a known miss: measured max |u - u_exact| / V0 = 0.088 at t = 0.1125 s, "
                   "dx = 5e-5, against the bar 0.008 that dx = 1e-4 meets (0.0026): with a wall speed of "
                   "1.25e-5 m/s the velocity noise the 0.02 % density tolerance allows is comparable to the "
                   "flow (docs/dfsph.md); runs.run('couette', dx=5e-5, solver='dfsph'), 12 s")
def test_a_moving_wall_drives_the_fluid_couette_refined():
    """The Couette start-up under DFSPH at dx = 5e-5 (L/20) held to the bar dx = 1e-4 meets
    (0.8 % at t = 0.1125 s). Expected to fail (measured 8.8 %); a pass means the fix."""
    out = runs.run("couette", dx=5e-5, solver="dfsph", times=(0.0225, 0.1125))
    assert not out.diverged
    assert out.metrics["linf_t0.1125"] < COUETTE_BAR, out.metrics


def test_a_scene_file_may_ask_for_dfsph(tmp_path, capsys):
    from taisph.formats.scenefile import load
    from taisph.scene.catalogue import find_scene_file

    path = find_scene_file("dam_break_probes_2d.toml")
    scene, settings = load(path, {"solver": "dfsph", "dx": 0.1})
    assert scene.solver == settings.solver == "dfsph"
    assert cli.main([str(path), "--solver", "dfsph", "--dx", "0.1", "--t-end", "0.02", "--frames", "1",
                     "--no-output", "--no-progress"]) == 0
    assert "solver dfsph" in capsys.readouterr().out


def test_the_divergence_solve_runs_when_it_has_work():
    """With a tolerance below the divergence error of every step the divergence solve
    iterates (by default it is skipped while the error is within 0.1 % before any
    iteration); it converges (dx = 0.05, to 0.2 s; 38 iterations a step on average) and
    the mean compression at the end is at most 0.08 % (measured 0.026 %)."""
    sim = taisph.Simulation(dfsph_scene(dx=0.05), dfsph_divergence_tolerance=1e-5)
    summary = sim.run(0.2, frames=1)
    stats = summary.pressure_solve
    assert stats["divergence_iterations_mean"] >= 1
    assert stats["divergence_error_max"] <= 1e-5
    assert mean_compression(sim) <= 0.0008
    assert ("dfsph", "divergence solve") in set(taisph.engine.kernels.TRACED)


def test_a_3d_dam_break_runs_incompressible():
    """3D (dx = 0.1; the 1 m wide, 2 m high column of the 2D case, 1 m deep) to Koshizuka &
    Oka's T = t sqrt(2 g/L) = 1.153 (t = 0.26 s): the solve converges (relaxation 0.3 in 3D),
    the mean compression is at most 0.0015 % (measured 0.00052 %), and the surge front
    (max x + dx/2)/L is within 0.10 of the experiment's 1.505 (measured 1.507)."""
    scene = dfsph_scene("dam_break_3d", dx=0.1)
    L, scale_T = ko_scales(scene)
    sim = taisph.Simulation(scene)
    summary = sim.run(1.153 / scale_T, frames=1)
    front = (sim.positions()[sim.fluid][:, 0].max() + scene.dx / 2) / L
    print(f"front {front:.3f}, mean compression {mean_compression(sim):.2e}")
    assert summary.pressure_solve["density_error_max"] <= sim.controls.dfsph_tolerance
    assert mean_compression(sim) <= 1.5e-5
    assert abs(front - 1.505) <= 0.10, front


def test_deterministic_runs_agree_bit_for_bit():
    """`--deterministic` under DFSPH: two runs of the dam break (dx = 0.04, 100 steps,
    no-slip dummy walls) on all the machine's threads (two in CI) end with identical
    positions and velocities. The walls' no-slip sums were once scattered from the fluid
    with atomic adds, whose order varied between runs: four such runs on two threads gave
    four different states."""
    scene = dfsph_scene(dx=0.04)
    runs_ = []
    for _ in range(2):
        sim = taisph.Simulation(scene, deterministic=True)
        assert "wall_velocity" in sim.solver.layout.vectors
        sim.step(100)
        runs_.append((sim.time, sim.positions(), sim.velocities()))
    assert runs_[0][0] == runs_[1][0]
    np.testing.assert_array_equal(runs_[0][1], runs_[1][1])
    np.testing.assert_array_equal(runs_[0][2], runs_[1][2])


def test_a_force_probe_reads_the_pressure_force_of_dfsph():
    """Issue 25 (1): a force probe under DFSPH sums the pressure force the fluid exerts on
    the walls from the solve's pressures (p_wall = p_i and the walls' hydrostatic head, as in
    DFSPH's momentum equation; it read 0 before). Still water (dx = 0.05, 0.3 s, sampled every
    step after the first 0.1 s): the force on the whole tank is the water's weight M g within
    0.35 % vertically at every sample (measured 0.115 % at worst; 0.3 % before DFSPH's
    still-water change) and has no horizontal part (below 1e-9 M g; measured 2e-15: the
    tank is symmetric)."""
    from taisph.probes import Probes, force

    scene = dfsph_scene("hydrostatic_tank", dx=0.05)
    sim = taisph.Simulation(scene, deterministic=True)
    sim.run(0.1, frames=1)
    probes = Probes([force("F", walls="tank")], walls={"tank": np.flatnonzero(scene.kind == taisph.WALL)})
    sim.run(0.3, frames=1, writers=[probes])
    weight = sim.total_mass() * 9.81
    sim.close()
    _, F = probes.series("F")
    assert len(F) > 10
    print(f"force/weight - 1: {np.abs(-F[:, 1] / weight - 1).max():.2e}, "
          f"max |F_x|/weight {np.abs(F[:, 0]).max() / weight:.1e}")
    assert np.all(np.abs(-F[:, 1] / weight - 1) < 0.0035), F[:, 1] / weight
    assert np.all(np.abs(F[:, 0]) < 1e-9 * weight), F[:, 0] / weight


@pytest.mark.parametrize("friction", [False, True])
def test_a_dfsph_force_probe_is_the_force_the_fluid_feels(friction):
    """Newton under DFSPH (symplectic Euler: a sample is the rate of the step from its
    time to the next): a dam break (dx = 0.05, to 0.3 s, sampled every step) changes the
    fluid's momentum by the sum over steps of dt (M g - F), F the force probe on the tank,
    to 1e-9 of M g T (measured ~1e-16 of it), without and with wall friction (the walls'
    artificial viscosity: the probe carries that shear force too)."""
    from taisph.probes import Probes, force

    scene = dfsph_scene(dx=0.05, wall_friction=friction)
    sim = taisph.Simulation(scene, deterministic=True)
    sim.step(1)  # the bootstrap's sample (t = 0) holds the warm start, not the first solve
    momentum0, t0, mass = sim.momentum(), sim.time, sim.total_mass()
    probes = Probes([force("F", walls="tank")], walls={"tank": np.flatnonzero(scene.kind == taisph.WALL)})
    sim.run(0.3, frames=1, writers=[probes])
    change = sim.momentum() - momentum0
    sim.close()
    times, F = probes.series("F")
    # one sample per step from t0; a batch of steps that reaches the end early ends with a
    # zero-length launch, whose evaluation at the end time is sampled too (its dt below is 0)
    assert times[0] == pytest.approx(t0, abs=1e-12) and len(times) in (sim.steps - 1, sim.steps)
    dt = np.diff(np.append(times, sim.time))
    expected = (dt[:, None] * (mass * np.array([0.0, -9.81]) - F)).sum(axis=0)
    assert np.all(np.abs(change - expected) < 1e-9 * mass * 9.81 * (sim.time - t0)), (change, expected)
    assert np.ptp(F[:, 1]) > 0.1 * mass * 9.81  # a real test: the force varies (the surge hits the wall)


def test_the_header_and_effects_say_what_dfsph_runs():
    """Issue 25 (2): DFSPH integrates with symplectic Euler whatever the scene's integrator
    (the cases default to pc): the header says the scene's integrator is not used, and
    ``sim.effects()`` lists the terms that run (DFSPH's kept ones), not those it replaced."""
    scene = dfsph_scene(dx=0.1)
    scene.integrator = "euler"
    assert "symplectic Euler; the scene's integrator euler is not used" in scene.describe()
    assert "the scene's integrator pc is not used" in dfsph_scene(dx=0.1).describe()
    sim = taisph.Simulation(scene)
    kept = [t.name for t in taisph.scene.solvers.dfsph_kept_terms(scene)]
    assert sim.effects() == kept and "gravity" in kept
    assert not {"continuity", "pressure", "dummy_walls", "density_diffusion"} & set(sim.effects())
    sim.close()
    wcsph = taisph.Simulation(taisph.cases.dam_break(dx=0.1))
    assert wcsph.effects() == [t.name for t in wcsph.scene.terms]
    wcsph.close()


def test_each_simulation_counts_its_own_solves():
    """Issue 25 (3): DFSPH's statistics belong to the simulation, not to the pooled fields
    it runs on: a second dam break (dx = 0.1, deterministic) on pooled fields
    reports the same iterations and host reads as the first, not their sum (nor those of
    whichever simulation used the fields before)."""
    def run():
        sim = taisph.Simulation(dfsph_scene(dx=0.1), deterministic=True)
        summary = sim.run(0.02, frames=1)
        sim.step(3)
        stats = dict(vars(sim.pressure_solve.stats))
        fields = sim.state.fields
        sim.close()
        return stats, summary.pressure_solve, fields

    first, summary1, fields1 = run()
    pooled = list(fields1.solver.field_sets)
    second, summary2, fields2 = run()
    assert any(fields2 is f for f in pooled)  # pooled fields were reused: the case the defect needs
    assert first["density_iterations"] > 0 and first["round_trips"] > 0
    assert second == first
    assert summary2 == summary1
