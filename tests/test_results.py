"""Headline results (taisph.run.results; issue 50: "the cylinder run prints no C_D"): a
case with a headline quantity prints it at the end of a run, with its unit, reference
and relative difference, and writes OUT/results.json; reporting only reads the run."""

import json
import math

import numpy as np
import pytest

import taisph
from taisph.cli.main import main as cli
from taisph.probes import Probes
from taisph.run import results
from taisph.run.results import Result, report
from taisph.scene import catalogue


def test_the_cylinder_run_prints_its_drag_coefficient(tmp_path, capsys):
    """python -m taisph cylinder (coarse, 0.01 s): the run ends with C_D, C_L and dp against
    Schaefer & Turek's values, and OUT/results.json holds each with its unit, reference,
    source and relative error, the scene's name and the simulated time."""
    out = tmp_path / "cyl"
    assert cli(["cylinder", "--dx", "0.01", "--t-end", "0.01", "--frames", "0", "--out", str(out),
                "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "headline results" in printed
    assert any(line.strip().startswith("C_D = ") and "reference 5.5795" in line for line in printed.splitlines())
    data = json.loads((out / "results.json").read_text())
    assert data["scene"] == "cylinder" and data["case"] == "cylinder" and data["time"] == pytest.approx(0.01)
    assert set(data["results"]) == {"C_D", "C_L", "dp"}
    assert {k: data["results"][k]["unit"] for k in data["results"]} == {"C_D": "1", "C_L": "1", "dp": "Pa"}
    c_d = data["results"]["C_D"]
    assert c_d["reference"] == 5.5795 and "Schaefer & Turek" in c_d["source"]
    assert c_d["relative_error"] == pytest.approx(c_d["value"] / 5.5795 - 1)
    assert "probes.csv" in c_d["note"]  # a mean over the run's probe records
    assert not list(out.glob(".results.json*"))  # written through a temporary file, renamed


def test_the_floating_box_reports_its_draft_and_reporting_changes_nothing(tmp_path):
    """From Python, mid-run: the floating box's draft against Archimedes' 0.25 m (a probe
    sampled now, the body's state); OUT/results.json only when an output folder is given;
    and the run goes on exactly as one that never reported (deterministic: bit for bit).
    The box is built at its Archimedes draft, so after 10 steps the draft is ~0.25 m by
    construction: asserted is what is reported, the gauge probe's level now less the body's
    bottom (its centre less half its height) to round-off, not the physics (tests/test_bodies.py)."""
    scene = taisph.cases.floating_box(dx=0.05)
    reported, plain = (taisph.Simulation(scene, deterministic=True) for _ in range(2))
    reported.step(10)
    assert report(scene, reported, None)[0] == "headline results:" and not list(tmp_path.iterdir())
    lines = report(scene, reported, tmp_path)
    assert lines[1].strip().startswith("draft = ") and "reference 0.25 m, Archimedes" in lines[1]
    draft = results.read(tmp_path)["results"]["draft"]
    gauge = Probes([q for q in scene.probes if q.name == "gauge"])
    gauge.sample(reported)
    level = float(gauge.values["gauge"][-1])
    gauge.close()
    bottom = float(reported.bodies()["box"].position[1]) - 0.5 * scene.case_parameters["box_height"]
    assert draft["unit"] == "m" and draft["value"] == pytest.approx(level - bottom, rel=0, abs=1e-12)
    reported.step(10)
    plain.step(20)
    assert np.array_equal(reported.positions(), plain.positions())
    assert np.array_equal(reported.velocities(), plain.velocities())
    reported.close()
    plain.close()


def test_a_scene_not_made_by_a_case_has_no_headline(tmp_path):
    """A case's scene renamed still has its case's headline; a scene whose recorded
    parameters are not its case's, one of no case, and a scene file's have none (nothing
    printed, no results.json)."""
    scene = taisph.cases.hydrostatic_tank(dx=0.1, t_end=0.01)
    scene.name = "my_tank"  # the name a user gave it: the case is what counts
    assert scene.case == "hydrostatic_tank" and catalogue.case_module(scene.case).headline
    sim = taisph.Simulation(scene)
    sim.step(2)
    lines = report(scene, sim, tmp_path)
    assert any("p_bottom" in line and "Pa" in line for line in lines)
    assert results.read(tmp_path)["scene"] == "my_tank"
    scene.case_parameters = {"dx": 0.1}  # not the case's parameters
    assert report(scene, sim, tmp_path / "other") == [] and not (tmp_path / "other").exists()
    scene.case = ""
    assert report(scene, sim, tmp_path / "other") == []
    assert report(scene, sim, tmp_path) == [] and not (tmp_path / "results.json").exists()  # not the last run's
    sim.close()
    from taisph.formats.scenefile import load

    loaded = load(catalogue.find_scene_file("dam_break_probes_2d.toml"), {"dx": 0.1})[0]
    assert loaded.case == "" and results.headline(loaded, None) == []


def test_a_result_line_and_its_json_entry():
    """The printed line: value, unit, reference with its source and the relative difference,
    then the note; a dimensionless unit is not printed; NaN is 'not measured' (null in JSON)."""
    r = Result("draft", 0.2475, "m", 0.25, "Archimedes", "at t = 3 s")
    assert r.line() == "draft = 0.2475 m (reference 0.25 m, Archimedes: -1.0 %; at t = 3 s)"
    assert r.relative_error == pytest.approx(-0.01)
    assert Result("C_D", 5.69, "1").line() == "C_D = 5.69"
    missing = Result("celerity", math.nan, "m/s", 1.365, "Boussinesq (1872)", "no crest yet")
    assert missing.line().startswith("celerity = not measured (reference 1.365 m/s")
    entry = missing.as_dict()
    assert entry["value"] is None and entry["relative_error"] is None and entry["reference"] == 1.365
    json.dumps(entry, allow_nan=False)


def test_every_case_with_a_headline_declares_it_as_a_function():
    """The plug-in: a case's headline is ``headline(sim, out)`` in its module; the cases the
    issue names have one."""
    for name in ("cylinder", "wave_flume", "floating_box", "solitary_wave", "water_entry", "dam_break", "sod",
                 "sedov", "channel", "hydrostatic_tank"):
        function = getattr(catalogue.case_module(name), "headline", None)
        assert callable(function), name
        assert list(__import__("inspect").signature(function).parameters) == ["sim", "out"], name
