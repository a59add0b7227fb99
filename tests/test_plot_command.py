"""``python -m taisph plot OUT`` ships with the package (issue 50: the plot tool ran only
from the repository's root, and put the cylinder's pressures (Pa) and the channel's flow
rate (m^2/s) on an axis labelled "surface (m)", as probes.csv recorded no unit): it draws
OUT/probes.png with one axis per quantity and unit, labelled from probes.json, from any
folder; a missing folder or CSV, an unknown --only name or a missing matplotlib is one
line and exit code 2."""

import os
import subprocess
import sys

import numpy as np
import pytest

import taisph
from taisph.cli import plot as command
from taisph.engine.layout import WALL
from taisph.probes import Probes, elevation, flow, force, pressure
from taisph.probes.plot import UNKNOWN, figure


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """A dam break (dx = 0.1) of a few steps with a pressure, an elevation, a force and a
    flow probe: OUT/probes.csv and OUT/probes.json."""
    out = tmp_path_factory.mktemp("run") / "out"
    scene = taisph.cases.dam_break(dx=0.1)
    sim = taisph.Simulation(scene)
    probes = Probes([pressure("P1", (0.3, 0.1)), pressure("P2", (0.5, 0.3)), elevation("H", 0.5),
                     force("floor", "walls"), flow("Q", (0.5, 0.0), (0.5, 1.0), every=2)],
                    walls={"walls": np.flatnonzero(scene.kind == WALL)}, path=out / "probes.csv")
    try:
        sim.run(6 * sim.dt, frames=1, writers=[probes])
    finally:
        probes.close()
        sim.close()
    return out


def test_one_axis_per_quantity_labelled_with_its_unit(run):
    fig, axes = figure(run)
    assert [(a.label, a.columns) for a in axes] == [("pressure (Pa)", ["P1", "P2"]),
                                                   ("surface elevation (m)", ["H"]),
                                                   ("force (N)", ["floor_x", "floor_y"]),
                                                   ("flow rate (m^2/s)", ["Q"])]
    assert [ax.get_ylabel() for ax in fig.axes] == [a.label for a in axes]
    lines = {line.get_label(): line for ax in fig.axes for line in ax.get_lines()}
    rows = [line.split(",") for line in (run / "probes.csv").read_text().splitlines()[1:]]
    assert len(lines["P1"].get_xdata()) == len(rows)
    assert len(lines["Q"].get_xdata()) == sum(r[-1] != "" for r in rows) < len(rows)  # Q every 2 steps: its own rows
    fig, axes = figure(run / "probes.csv", only=["floor", "H"])
    assert [a.label for a in axes] == ["surface elevation (m)", "force (N)"]


def test_the_command_writes_the_png_from_any_folder(run, tmp_path):
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    done = subprocess.run([sys.executable, "-m", "taisph", "plot", str(run)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == (f"wrote {run / 'probes.png'}: pressure (Pa), surface elevation (m), force (N), "
                                   "flow rate (m^2/s)")
    assert (run / "probes.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    image = tmp_path / "p.svg"
    assert command.main([str(run / "probes.csv"), "--out", str(image), "--only", "P1"]) == 0
    assert image.read_text().startswith("<?xml")


@pytest.mark.parametrize("argv, message", [
    (["{tmp}/nowhere"], "{tmp}/nowhere: no such folder"),
    (["{tmp}/nowhere.csv"], "{tmp}/nowhere.csv: no such file"),
    (["{tmp}"], "{tmp}: no probes.csv in it (a run writes one with --probe, or a case's or a scene file's probes)"),
    (["{run}", "--only", "P9"], "{run}/probes.csv: none of P9 among its probes (P1, P2, H, floor_x, floor_y, Q)"),
    (["{run}", "--out", "{tmp}/no/such/p.png"], "--out {tmp}/no/such/p.png: no folder {tmp}/no/such"),
])
def test_a_refusal_is_one_line_and_exit_code_2(run, tmp_path, capsys, argv, message):
    argv = [a.format(tmp=tmp_path, run=run) for a in argv]
    assert command.main(argv) == 2
    assert capsys.readouterr().err.splitlines() == [f"taisph: error: {message.format(tmp=tmp_path, run=run)}"]


def test_without_matplotlib_it_says_what_to_install(run, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib: ImportError
    assert command.main([str(run)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and 'pip install "taisph[plot]"' in err[0] and err[0].startswith("taisph: error: plot needs")


def test_help_and_no_abbreviations(capsys):
    assert command.main(["--help"]) == 0
    assert "one axis per" in capsys.readouterr().out
    assert command.main(["x", "--on", "P1"]) == 2  # not taken for --only
    assert "unrecognized arguments: --on P1" in capsys.readouterr().err


def test_a_csv_without_units_keeps_pressures_off_the_metres(tmp_path):
    """An older CSV (no probes.json): unknown units, split by magnitude, never labelled as
    a surface elevation; a body's columns by their names."""
    path = tmp_path / "probes.csv"
    path.write_text("time,P,H,box_x,box_y,box_angle,box_vx,box_vy,box_omega,box_fx,box_fy\n"
                    + "".join(f"{0.1 * k},{1000 + k},{0.5 + 0.01 * k},1,2,0,0,0,0,0,-9.8\n" for k in range(3)))
    _, axes = figure(path)
    labels = {a.label: a.columns for a in axes}
    assert labels[f"{UNKNOWN} (no probes.json; |values| >= 100)"] == ["P"]
    assert labels[f"{UNKNOWN} (no probes.json; |values| < 100)"] == ["H"]
    assert labels["body position (m)"] == ["box_x", "box_y"] and labels["body force (N)"] == ["box_fx", "box_fy"]
