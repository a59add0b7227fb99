"""The seed's command line: ``run`` on particle files writes fluid.dat and ParaView
frames; ``export`` writes a case as files plus a command that reproduces the case."""

import math
import shlex

import numpy as np
import pytest

import taisph
from taisph.engine.timestep import fixed_dt
import taisph.geometry
from taisph.formats import seed
from taisph.cli import main as cli
from taisph.formats import dat as seedio
from taisph.run import vtk
from taisph.eos import tait


def export(tmp_path, capsys, case, params):
    dat = tmp_path / "dat"
    argv = ["export", case, "--dat", str(dat)]
    for key, value in params.items():
        argv += ["--set", f"{key}={value}"]
    assert cli.main(argv) == 0
    printed = capsys.readouterr().out
    command = printed.strip().splitlines()[-1]
    assert command.startswith("python -m taisph run ")
    assert (dat / "run.txt").read_text().splitlines()[1] == command
    return dat, shlex.split(command)[3:]  # argv after "python -m taisph"


@pytest.mark.parametrize("case,params", [
    ("dam_break_wedge", {"dx": 0.08}),
    ("two_fluids", {"dx": 0.05}),
    ("drop_on_incline", {"dim": 3, "dx": 0.1}),
])
def test_export_then_run_equals_the_case(tmp_path, capsys, case, params):
    """Running the exported files with the printed command gives the same positions,
    velocities and densities as running the case directly: equal to 1e-12 of the
    displacement (measured: bit for bit), at every output frame of 30 steps."""
    dat, argv = export(tmp_path, capsys, case, params)
    scene = taisph.cases.CASES[case](**params)
    # the seed's command line takes a fixed DT: export writes the scene's stable step
    sim = taisph.Simulation(scene, dt=fixed_dt(scene))
    t_end = 30 * sim.dt
    files = 2 if scene.n_wall else 1
    assert float(argv[2 + files]) == sim.dt  # DT printed exactly
    argv[1 + files] = repr(t_end)
    out = tmp_path / "out"
    argv += ["--frames", "3", "--out", str(out), "--no-progress"]
    assert cli.main(argv) == 0
    frames = seedio.read_output(out / "fluid.dat")
    assert [f.step for f in frames] == [0, 1, 2, 3]
    direct = []
    sim.run(t_end, frames=3, callback=lambda s: direct.append((s.time, s.positions()[s.fluid],
                                                               s.velocities()[s.fluid], s.density()[s.fluid])))
    x0 = scene.position[scene.kind == taisph.FLUID]
    for frame, (t, x, v, rho) in zip(frames[1:], direct):
        assert frame.time == t
        moved = np.abs(x - x0).max()
        assert moved > 0
        np.testing.assert_array_equal(frame.index, np.arange(scene.n_fluid))
        assert np.abs(frame.position - x).max() <= 1e-12 * moved
        assert np.abs(frame.velocity - v).max() <= 1e-12 * np.abs(v).max()
        assert np.abs(frame.density - rho).max() <= 1e-12 * rho.max()
    entries = vtk.read_pvd(out / f"{scene.name}.pvd")
    assert [t for t, part, _ in entries if part == 0] == pytest.approx([f.time for f in frames], rel=1e-9)


def test_run_output_columns(tmp_path, capsys):
    """fluid.dat: every frame lists every fluid particle in index order; mass constant;
    pressure is the Tait pressure of the density (the input's pressure column is
    ignored); the energy column is carried through unchanged."""
    x = taisph.geometry.lattice([0, 0], [0.4, 0.2], 0.02)
    n = len(x)
    rng = np.random.default_rng(3)
    energy = rng.uniform(1, 2, n)
    init = seedio.write_particles(tmp_path / "block.dat", x, np.zeros_like(x), 0.4, 1000.0,
                                  np.full(n, 12345.0), energy)
    walls = taisph.geometry.box_walls([0, 0], [0.4, 0.4], 0.01)
    wall_file = seedio.write_particles(tmp_path / "walls.dat", walls, np.zeros_like(walls), 0.4, 1000.0, 0.0)
    out = tmp_path / "out"
    assert cli.main(["run", str(init), str(wall_file), "0.01", "0.0005", "eulermom", "gaussian",
                     "--frames", "2", "--out", str(out), "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "pressure column of the input: not used" in printed
    frames = seedio.read_output(out / "fluid.dat")
    assert [f.time for f in frames] == pytest.approx([0, 0.005, 0.01], abs=1e-15)
    c0 = 10 * math.sqrt(2 * 9.81 * 0.19)  # default: H = top fluid particle above the floor
    for f in frames:
        np.testing.assert_array_equal(f.index, np.arange(n))
        np.testing.assert_array_equal(f.energy, energy)
        np.testing.assert_array_equal(f.mass, 0.4)
        np.testing.assert_allclose(f.pressure, tait.pressure(f.density, 1000.0, c0), rtol=1e-9, atol=1e-6)
    assert frames[-1].position[:, 1].min() < x[:, 1].min()  # it moved (fell onto the floor)
    assert (out / "block.pvd").exists() and (out / "walls.vtu").exists()


def test_defaults_from_files(tmp_path, capsys):
    """Without options, run's parameters follow the dam-break conventions from the files:
    h = 1.3 dx, r0 = wall spacing, D = 5 g H / r0, c0 = 10 sqrt(2 g H), water Tait."""
    dat, _ = export(tmp_path, capsys, "dam_break_wedge", {"dx": 0.08})
    scene, energy = seed.load_scene(dat / "particles.dat", dat / "boundary.dat")
    case = taisph.cases.dam_break_wedge(dx=0.08)
    H = case.position[case.kind == 0, 1].max()  # top fluid particle above the floor (y = 0)
    p = scene.parameters()
    assert scene.smoothing_length == pytest.approx(1.3 * 0.08, rel=1e-12)
    assert p["lj_cutoff"] == pytest.approx(0.04, rel=1e-12)
    assert p["lj_strength"] == pytest.approx(5 * 9.81 * H / 0.04, rel=1e-12)
    assert scene.materials[0].c0 == pytest.approx(10 * math.sqrt(2 * 9.81 * H), rel=1e-12)
    assert (scene.materials[0].rho0, scene.materials[0].gamma) == (1000.0, 7.0)
    assert [t.name for t in scene.terms] == [t.name for t in case.terms]
    np.testing.assert_array_equal(energy, 0.0)


def test_two_materials_from_density(tmp_path, capsys):
    """--rho0 with two values: each particle gets the material whose rho0 is nearest its
    density, and the multiphase formulation is chosen automatically."""
    dat, _ = export(tmp_path, capsys, "two_fluids", {"dx": 0.1})
    scene, _ = seed.load_scene(dat / "particles.dat", dat / "boundary.dat", seed.Physics(rho0=[1000.0, 500.0]))
    case = taisph.cases.two_fluids(dx=0.1)
    np.testing.assert_array_equal(scene.material, case.material)
    assert [t.name for t in scene.terms][:2] == ["continuity_colagrossi", "pressure_hu_adams"]


def test_unstable_run_is_reported(tmp_path, capsys):
    """Forward Euler at dt = 0.001 s, more than twice the case's stable step at dx = 0.1
    (2.4x when written: the premise, asserted one-sided), blows up within 0.5 s (densities
    go negative): exit code 1 and a hint."""
    dat, argv = export(tmp_path, capsys, "dam_break_wedge", {"dx": 0.1})
    assert 0.001 > 2 * float(argv[4]), argv
    argv[3], argv[4], argv[5] = "0.5", "0.001", "euler"
    assert cli.main(argv + ["--frames", "1", "--out", str(tmp_path / "out"), "--no-progress"]) == 1
    err = capsys.readouterr().err
    assert "unstable" in err and "from rho0" in err


def test_export_refuses_what_files_cannot_hold(tmp_path):
    scene = taisph.cases.dam_break(dx=0.2, seed_physics=True)
    scene.terms = scene.terms[:3]  # no gravity, no walls term
    with pytest.raises(ValueError, match="cannot export"):
        seed.export_scene(scene, tmp_path / "x")
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("integrator", ["euler", "pc"])
def test_boundary_velocity_moves_walls(tmp_path, integrator):
    """The boundary file's u, v move the walls rigidly: after n steps every wall particle
    has moved by u n dt (to round-off)."""
    x = taisph.geometry.lattice([0.2, 0.2], [0.4, 0.4], 0.02)
    init = seedio.write_particles(tmp_path / "p.dat", x, np.zeros_like(x), 0.4, 1000.0, 0.0)
    walls = taisph.geometry.box_walls([0, 0], [1, 1], 0.01)
    wall_file = seedio.write_particles(tmp_path / "w.dat", walls, np.tile([0.5, 0.0], (len(walls), 1)), 0.4,
                                       1000.0, 0.0)
    scene, _ = seed.load_scene(init, wall_file, integrator=integrator, dt=1e-4)
    sim = taisph.Simulation(scene)
    sim.step(20)
    moved = sim.positions()[sim.wall] - walls
    np.testing.assert_allclose(moved, np.tile([0.5 * 20 * 1e-4, 0.0], (len(walls), 1)), rtol=0, atol=1e-12)
