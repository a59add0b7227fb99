"""The command line refuses bad numbers with the option's or parameter's name, the value
and the allowed range, with exit code 2 and nothing written; ``CASE --help`` shows each
parameter's range; the seed's scene logic (taisph.formats.seed) does not import the command line."""

import os
import subprocess
import sys

import pytest

import taisph
from taisph.cli import main as cli
from taisph.scene import catalogue
from taisph.scene.parameters import ParameterError


def test_dam_break_negative_dx_exits_2_and_writes_nothing(tmp_path):
    """The issue's example, as a user types it: exit code 2, the option, value and range
    on stderr (no numpy message), and no output folder."""
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    done = subprocess.run([sys.executable, "-m", "taisph", "dam_break", "--dx", "-1"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 2
    assert "taisph: error: argument --dx: must be > 0, got -1" in done.stderr
    assert "samples" not in done.stderr and "Traceback" not in done.stderr
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv,message", [
    (["--t-end", "0"], "argument --t-end: must be in (0, 100000], got 0"),
    (["--dt", "-0.001"], "argument --dt: must be > 0, got -0.001"),
    (["--dt", "abc"], "argument --dt: expected a number, got 'abc'"),
    (["--frames", "-1"], "argument --frames: must be an integer in [0, 100000], got -1"),
    (["--frames", "2.5"], "argument --frames: expected an integer, got '2.5'"),
    (["--threads", "0"], "argument --threads: must be an integer >= 1, got 0"),
    (["--checkpoint-every", "-2"], "argument --checkpoint-every: must be an integer >= 1, got -2"),
    (["--max-density-error", "-0.1"], "argument --max-density-error: must be >= 0, got -0.1"),
    (["--neighbour-skin", "3"], "argument --neighbour-skin: must be in [0, 2], got 3"),
    (["--dx", "nan"], "argument --dx: must be > 0, got nan"),
    (["--dx", "5"], "dam_break: dx = 5 m leaves the water column (width = 1 m, height = 2 m) without particles "
                    "along width: dx must be at most 1 m"),
    (["--set", "alpha=-1"], "dam_break: alpha must be in [0, 2], got -1.0"),
    (["--set", "walls=wood"], "--set walls=wood: walls must be one of 'lj', 'dummy' or None; expected one of lj, "
                              "dummy, got 'wood'"),
    (["--set", "closed_top=maybe"], "--set closed_top=maybe: closed_top must be True or False; expected true or "
                                    "false, got 'maybe'"),
    (["--set", "width"], "--set width: expected NAME=VALUE"),
])
def test_case_command_refuses_out_of_range(tmp_path, capsys, argv, message):
    out = tmp_path / "out"
    assert cli.main(["dam_break", *argv, "--out", str(out), "--no-progress"]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("argv,message", [
    (["run", "p.dat", "1", "0.001", "pc", "spline", "--alpha", "-1"], "argument --alpha: must be in [0, 2], got -1"),
    (["run", "p.dat", "1", "0.001", "pc", "spline", "--rho0", "1000,-5"],
     "argument --rho0: each value must be > 0, got -5 in 1000,-5"),
    (["run", "p.dat", "1", "0.001", "pc", "spline", "--frames", "0"], "argument --frames: must be an integer in [1, 100000]"),
    (["run", "p.dat", "1", "0.001", "pc", "spline", "--lj-cutoff", "0"], "argument --lj-cutoff: must be > 0, got 0"),
    (["export", "dam_break", "--dat", "DAT", "--dx", "0"], "argument --dx: must be > 0, got 0"),
    (["export", "dam_break", "--dat", "DAT", "--set", "g=-9.81"], "dam_break: g must be in (0, 1000], got -9.81"),
    (["export", "no_such_case", "--dat", "DAT"], "unknown case 'no_such_case'; cases: channel, couette, cylinder, dam_break"),
])
def test_seed_commands_refuse_out_of_range(tmp_path, capsys, argv, message):
    argv = [str(tmp_path / a) if a in ("p.dat", "DAT") else a for a in argv]
    assert cli.main(argv + (["--out", str(tmp_path / "out")] if argv[0] == "run" else [])) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_python_and_command_line_say_the_same(capsys):
    """dam_break(h_factor=0.4) from Python and --set h_factor=0.4: the same message."""
    with pytest.raises(ParameterError) as err:
        taisph.cases.dam_break(h_factor=0.4)
    assert str(err.value) == "dam_break: h_factor must be in (0.5, 3], got 0.4"
    assert cli.main(["dam_break", "--set", "h_factor=0.4", "--no-output", "--no-progress"]) == 2
    assert capsys.readouterr().err.strip() == f"taisph: error: {err.value}"


def test_case_help_shows_each_parameter_range(capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(["sod", "--help"])
    assert exit_.value.code == 0
    lines = capsys.readouterr().out.splitlines()
    row = {line.split()[0]: line for line in lines if line.startswith("  ") and " = " in line}
    assert row["dx"].split() == ["dx", "=", "0.00125", ">", "0"]
    assert row["courant"].split() == ["courant", "=", "0.2", "in", "(0,", "1]"]
    assert row["spacing"].split() == ["spacing", "=", "'equal_mass'", "one", "of", "'equal_mass',", "'equal_spacing'"]
    assert row["left"].endswith("(rho, u, p) with rho > 0, u a finite number, p > 0")
    assert row["frames"].endswith("an integer in [0, 100000]")


def test_set_parses_by_the_declared_range(tmp_path, capsys):
    """--set values take the parameter's kind: a tuple, a flag, none, an integer."""
    assert catalogue.parse_setting("sod", "left=(2,0,3)") == ("left", (2.0, 0.0, 3.0))
    assert catalogue.parse_setting("sod", "variable-h=off") == ("variable_h", False)
    assert catalogue.parse_setting("dam_break", "c0=none") == ("c0", None)
    assert catalogue.parse_setting("drop_on_incline", "dim=3") == ("dim", 3)


def test_seed_does_not_import_the_command_line(tmp_path):
    """Building scenes from seed files and writing them (taisph.formats.seed) loads no module of
    taisph.cli and no argparse-based command: the import cycle of issue 12 is gone."""
    code = (
        "import sys, taisph.formats.seed as seed, taisph\n"
        f"argv = seed.export_scene(taisph.cases.dam_break_wedge(dx=0.2), {str(tmp_path)!r})\n"
        f"scene, _ = seed.load_scene({str(tmp_path / 'particles.dat')!r}, {str(tmp_path / 'boundary.dat')!r})\n"
        "print(scene.n_fluid, sorted(m for m in sys.modules if m.startswith('taisph.cli')))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-2:] == ["50", "[]"]


@pytest.mark.parametrize("name", sorted(catalogue.registry()))
def test_help_shows_each_cases_real_defaults(name):
    """`CASE --help` states what a run without the option does: the default scene's dx,
    end time, frames, integrator, kernel, and the Courant number the simulation will use
    (timestep.controls_for, as taisph.Simulation sets it up)."""
    from taisph.engine.timestep import controls_for

    parser = cli.build_parser(name)
    helps = {a.option_strings[0]: " ".join(a.help.split()) for a in parser._actions if a.option_strings}
    scene = catalogue.find(name)()
    assert helps["--dx"].endswith(f"this case: {scene.dx:g} m")
    assert helps["--t-end"].endswith(f"this case: {scene.t_end:g} s")
    assert helps["--frames"].endswith(f"this case: {scene.frames}")
    assert helps["--integrator"].endswith(f"this case: {scene.integrator}")
    assert helps["--kernel"].endswith(f"this case: {scene.kernel}")
    assert helps["--courant"].endswith(f"this case: {controls_for(scene).courant:g}")
