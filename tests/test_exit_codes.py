"""Exit codes of the command line (issue 24): only taisph's own input errors
(:class:`taisph.messages.InputError`) are "input refused", exit code 2 with one line
``taisph: error: MESSAGE``; any other exception is a fault of taisph and keeps its
traceback (exit code 1), even a TypeError, KeyError, ValueError or FileNotFoundError;
a path that does not exist is an input error naming the path. ``Scene.set`` checks
every value before writing any."""

import os
import subprocess
import sys

import pytest

import taisph
from taisph.cli import case as cli_case
from taisph.cli import main as cli
from taisph.messages import InputError


def run_python(*argv, cwd=None):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    return subprocess.run([sys.executable, *argv], cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize("error", [TypeError, KeyError, ValueError, FileNotFoundError])
def test_a_fault_of_taisph_is_not_refused_input(monkeypatch, tmp_path, error):
    """A programming error in a run (here the run itself raising) propagates out of
    main(): before, guarded() turned these four into "input refused", exit code 2."""

    def broken(*args, **kwargs):
        raise error("a bug in taisph")

    monkeypatch.setattr(cli_case, "simulate", broken)
    with pytest.raises(error, match="a bug in taisph"):
        cli.main(["dam_break", "--dx", "0.1", "--out", str(tmp_path / "out"), "--no-progress"])


def test_a_fault_of_taisph_exits_1_with_its_traceback(tmp_path):
    """As a user sees it: exit code 1, Python's traceback ending in the TypeError, no
    ``taisph: error:`` line."""
    code = ("import sys\n"
            "import taisph.cli.case as case\n"
            "from taisph.cli.main import main\n"
            "def broken(*args, **kwargs):\n"
            "    raise TypeError('a bug in taisph')\n"
            "case.simulate = broken\n"
            "sys.exit(main(['dam_break', '--dx', '0.1', '--no-progress']))\n")
    done = run_python("-c", code, cwd=tmp_path)
    assert done.returncode == 1, done.stderr
    assert "Traceback (most recent call last)" in done.stderr
    assert done.stderr.rstrip().splitlines()[-1] == "TypeError: a bug in taisph"
    assert "taisph: error" not in done.stderr


def test_a_bad_parameter_exits_2_with_one_line(tmp_path):
    done = run_python("-m", "taisph", "dam_break", "--set", "alpha=-1", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr.splitlines() == ["taisph: error: dam_break: alpha must be in [0, 2], got -1.0"]
    assert list(tmp_path.iterdir()) == []


def test_a_missing_scene_file_exits_2_naming_it(tmp_path):
    done = run_python("-m", "taisph", "no_such_scene.toml", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert done.stderr.splitlines() == ["taisph: error: no_such_scene.toml: no such scene file"]


def test_a_missing_seed_file_exits_2_naming_it(tmp_path, capsys):
    path = tmp_path / "particles.dat"
    assert cli.main(["run", str(path), "1", "0.001", "pc", "spline", "--out", str(tmp_path / "out")]) == 2
    assert capsys.readouterr().err.splitlines() == [f"taisph run: error: {path}: no such particle file"]
    assert list(tmp_path.iterdir()) == []


def test_a_scene_file_option_out_of_range_exits_2(tmp_path, capsys):
    """The scene-file command parsed its options outside guarded(): ``SCENE.toml --dx -1``
    ended in a traceback."""
    assert cli.main(["dam_break_probes_2d.toml", "--dx", "-1", "--out", str(tmp_path / "out")]) == 2
    assert "taisph: error: argument --dx: must be > 0, got -1" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_the_input_errors_are_input_errors():
    """Each of taisph's refusals of input is an InputError, and still a ValueError."""
    from taisph.cli.parser import UsageError
    from taisph.formats.dat import SeedFileError
    from taisph.formats.scenefile_spec import SceneFileError
    from taisph.scene.parameters import ParameterError

    for cls in (ParameterError, UsageError, SceneFileError, SeedFileError):
        assert issubclass(cls, InputError) and issubclass(cls, ValueError), cls
    with pytest.raises(InputError, match="alpha must be in"):
        taisph.cases.dam_break(alpha=-1)
    scene = taisph.cases.dam_break(dx=0.1)
    scene.terms = [t for t in scene.terms if t.name != "continuity"]
    with pytest.raises(InputError, match="needs the 'continuity' term|needs the continuity equation"):
        scene.validate()  # a term's check(scene)
    scene = taisph.cases.dam_break(dx=0.1, walls="dummy")
    scene.neighbour_skin = 0.5
    scene.solver = "dfsph"
    with pytest.raises(InputError, match="solver='dfsph' builds its own pair list"):
        scene.validate()  # the solver's rules
    scene = taisph.cases.dam_break(dx=0.1)
    scene.kernel = "box"
    with pytest.raises(InputError, match="unknown kernel 'box'"):
        scene.validate()  # the scene's own checks


def test_scene_set_refused_leaves_the_scene_unchanged():
    """One good value and one bad: nothing is written (before, alpha was changed and
    then rho0 refused, leaving a half-changed scene)."""
    scene = taisph.cases.dam_break(dx=0.1)
    before = scene.parameters()
    materials = [(m.rho0, m.c0, m.gamma) for m in scene.materials]
    h = scene.smoothing_length
    for bad in (dict(alpha=0.05, rho0=-1.0), dict(rho0=500.0, gravity=(0.0,)), dict(smoothing_length=0.5, c0="fast"),
                dict(alpha=0.05, smoothing_length=-1.0)):
        with pytest.raises(ValueError):
            scene.set(**bad)
        assert scene.parameters() == before, bad
        assert [(m.rho0, m.c0, m.gamma) for m in scene.materials] == materials, bad
        assert scene.smoothing_length == h, bad
    with pytest.raises(KeyError, match="no parameter 'nonsense'"):
        scene.set(alpha=0.05, nonsense=1)
    assert scene.parameters() == before
    scene.set(alpha=0.05, rho0=500.0)  # good values are written, to every material
    assert scene.parameters()["alpha"] == 0.05 and [m.rho0 for m in scene.materials] == [500.0] * len(materials)


def test_material_set_refused_leaves_the_material_unchanged():
    material = taisph.Material()
    with pytest.raises(InputError, match="c0 must be a positive number"):
        material.set(rho0=2000.0, c0=-1.0)
    assert (material.rho0, material.c0) == (1000.0, 50.0)
    with pytest.raises(KeyError):
        material.set(rho0=2000.0, name="oil")
    assert material.rho0 == 1000.0


def test_simulation_set_refused_leaves_the_simulation_unchanged():
    """A control (dt) and a bad scene value (rho0 = -1): neither is written."""
    sim = taisph.Simulation(taisph.cases.hydrostatic_tank(dx=0.1))
    dt, rho0 = sim.controls.dt, sim.scene.materials[0].rho0
    with pytest.raises(ValueError, match="rho0 must be a positive number"):
        sim.set(dt=1e-5, rho0=-1.0)
    assert (sim.controls.dt, sim.scene.materials[0].rho0) == (dt, rho0)
    sim.set(dt=1e-5, rho0=990.0)
    assert (sim.controls.dt, sim.scene.materials[0].rho0) == (1e-5, 990.0)
    sim.close()


def test_an_abbreviated_option_is_refused_not_guessed(tmp_path, capsys):
    """``--frame 3`` is not taken for ``--frames 3`` (issue 50): argparse's prefix matching
    is off, so a misspelt option is refused as input (exit 2) and the run never starts."""
    code = cli.main(["dam_break", "--dx", "0.1", "--frame", "3", "--out", str(tmp_path / "out"), "--no-progress"])
    assert code == 2 and "unrecognized arguments: --frame 3" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_closed_simulation_says_so():
    """After close(): reading, stepping, running or setting says the simulation was closed
    (issue 50: positions() raised AttributeError on None)."""
    sim = taisph.Simulation(taisph.cases.hydrostatic_tank(dx=0.1))
    sim.step(1)
    sim.close()
    for call in (sim.density, lambda: sim.step(1), lambda: sim.run(0.01), lambda: sim.set(alpha=0.1)):
        with pytest.raises(RuntimeError, match="this simulation was closed"):
            call()


@pytest.mark.parametrize("inside", [False, True])
def test_an_output_folder_that_cannot_be_made_is_refused_first(tmp_path, capsys, inside):
    """``--out`` naming a file, or a folder inside a file, is refused as input (exit 2, the
    path and why) before the kernels compile (issue 50: FileExistsError / NotADirectoryError
    after the compilation, exit 1)."""
    blocker = tmp_path / "results.txt"
    blocker.write_text("not a folder")
    out = blocker / "run" if inside else blocker
    code = cli.main(["dam_break", "--dx", "0.1", "--out", str(out), "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2 and f"--out {out}: " in err and "is a file, not a folder" in err
    assert blocker.read_text() == "not a folder"
