"""Scene files with phases: a material's dynamic viscosity and background pressure,
surface tension (physics.surface_tension), and fluids of different rho0 with dummy walls
(the sharp-interface terms with the walls in their sums, taisph.scene.phases). Each new
key reaches the built scene, each bad value is refused naming the file, the key and the
value, and a two-phase scene with dummy walls runs."""

import re

import numpy as np
import pytest

import taisph
from taisph.cli.main import main as cli
from taisph.formats.scenefile import SceneFileError, load, read

# water under air in a closed box, dummy walls; the keys this file adds: viscosity, background_pressure,
# surface_tension (alpha = 0: the physical viscosity only)
TWO = """\
name = "layers"
dim = 2
dx = 0.025
t_end = 0.1
frames = 1
solver = "wcsph"

[physics]
gravity = [0.0, -9.81]
alpha = 0.0
surface_tension = 0.0728

[[materials]]
name = "water"
rho0 = 1000.0
viscosity = 1e-3
background_pressure = 100.0

[[materials]]
name = "air"
rho0 = 1.2
c0 = 500.0
viscosity = 1.8e-5
background_pressure = 100.0

[[fluid]]
box = [[0.0, 0.0], [0.5, 0.25]]
material = "water"

[[fluid]]
box = [[0.0, 0.25], [0.5, 0.5]]
material = "air"

[[walls]]
name = "box"
box = [[0.0, 0.0], [0.5, 0.5]]
open_top = false
"""

# one liquid in an open tank (the free-surface form of surface tension)
ONE = """\
name = "pool"
dim = 2
dx = 0.025
t_end = 0.1
frames = 1
solver = "wcsph"

[physics]
surface_tension = 0.0728

[[materials]]
name = "water"
viscosity = 1e-3

[[fluid]]
box = [[0.0, 0.0], [0.5, 0.25]]

[[walls]]
box = [[0.0, 0.0], [0.5, 0.5]]
"""


def scene_file(tmp_path, text=TWO, name="phases.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_phase_keys_reach_the_built_scene(tmp_path):
    scene, settings = load(scene_file(tmp_path))
    water, air = scene.materials
    assert (water.viscosity, water.background_pressure, air.viscosity, air.background_pressure) == (1e-3, 100.0,
                                                                                                    1.8e-5, 100.0)
    terms = scene.terms_by_name
    assert terms["surface_tension"].values["sigma"] == 0.0728
    assert terms["surface_tension"].free_surface is False  # two materials: the two-phase form
    assert terms["phase_viscosity"].options["walls"] is True  # dummy walls: no-slip
    assert terms["continuity_colagrossi"].options["walls"] and terms["pressure_hu_adams"].options["walls"]
    assert "dummy_walls" in terms
    # no density diffusion across the interface unless the file sets delta; no Morris viscosity beside it
    assert "density_diffusion" not in terms and "laminar_viscosity" not in terms
    # the run's header says which phases and models run
    phases, models = settings.notes[:2]
    assert phases == ("phases: water (rho0 = 1000 kg/m^3, viscosity 0.001 Pa s), "
                      "air (rho0 = 1.2 kg/m^3, viscosity 1.8e-05 Pa s)")
    assert models.startswith("models: sharp interface (Colagrossi & Landrini continuity, Hu & Adams pressure, "
                             "dummy walls in both)")
    for part in ("viscosity per phase (Hu & Adams 2006, no-slip walls)",
                 "surface tension sigma = 0.0728 N/m between water and air (CSF)", "background pressure 100 Pa"):
        assert part in models
    assert settings.notes[2].startswith("wall group box:")
    # delta set in the file is kept
    scene, _ = load(scene_file(tmp_path, TWO.replace("alpha = 0.0", "alpha = 0.0\ndelta = 0.05")))
    assert scene.terms_by_name["density_diffusion"].values["delta"] == 0.05


def test_lennard_jones_walls_keep_the_walls_out_of_the_phase_terms(tmp_path):
    scene, _ = load(scene_file(tmp_path, TWO.replace("open_top = false", 'open_top = false\nmodel = "lj"')))
    terms = scene.terms_by_name
    assert terms["phase_viscosity"].options["walls"] is False
    assert not terms["continuity_colagrossi"].options["walls"] and not terms["pressure_hu_adams"].options["walls"]
    assert "lennard_jones_wall" in terms and "dummy_walls" not in terms
    assert terms["density_diffusion"].values["delta"] == 0.1  # as before: only dummy walls turn its default off


def test_one_material_takes_the_free_surface_form_and_its_viscosity(tmp_path):
    scene, settings = load(scene_file(tmp_path, ONE))
    terms = scene.terms_by_name
    assert terms["surface_tension"].free_surface is True
    assert terms["surface_tension"].values["sigma"] == 0.0728
    assert terms["phase_viscosity"].options["walls"] is True
    assert scene.materials[0].viscosity == 1e-3 and scene.materials[0].background_pressure == 0.0
    assert settings.notes[0] == "phases: water (rho0 = 1000 kg/m^3, viscosity 0.001 Pa s)"
    assert "surface tension sigma = 0.0728 N/m at water's free surface (CSF)" in settings.notes[1]
    # a plain scene of water gets no phase lines, as before
    plain = ONE.replace("surface_tension = 0.0728", "").replace("viscosity = 1e-3", "")
    _, settings = load(scene_file(tmp_path, plain))
    assert not any(n.startswith(("phases:", "models:")) for n in settings.notes)
    assert {"surface_tension", "phase_viscosity"}.isdisjoint(load(scene_file(tmp_path, ONE.replace(
        "surface_tension = 0.0728", "surface_tension = 0.0").replace("viscosity = 1e-3", "viscosity = 0.0")))[0]
        .terms_by_name)  # 0: none, as the other physics keys


BAD = [  # (old text, new text, key, value shown, problem)
    ("viscosity = 1e-3", "viscosity = -1e-3", "materials[0].viscosity", "-0.001", "must be in [0, 1e+06]"),
    ("viscosity = 1e-3", 'viscosity = "thick"', "materials[0].viscosity", "'thick'", "expected a number"),
    ("viscosity = 1.8e-5", "viscosity = 1e7", "materials[1].viscosity", "10000000.0", "must be in [0, 1e+06]"),
    ("viscosity = 1e-3\nbackground_pressure = 100.0", "viscosity = 1e-3\nbackground_pressure = -5.0",
     "materials[0].background_pressure", "-5.0", "must be in [0, 1e+09]"),
    ("viscosity = 1e-3\nbackground_pressure = 100.0", "viscosity = 1e-3\nbackground_pressure = true",
     "materials[0].background_pressure", "True", "expected a number"),
    ("surface_tension = 0.0728", "surface_tension = -0.07", "physics.surface_tension", "-0.07",
     "must be in [0, 1000]"),
    ("surface_tension = 0.0728", "surface_tension = nan", "physics.surface_tension", "nan", "must be in [0, 1000]"),
    ("surface_tension = 0.0728", 'surface_tension = "water"', "physics.surface_tension", "'water'",
     "expected a number"),
    ("alpha = 0.0", "alpha = 0.0\nnu = 1e-6", "physics.nu", "1e-06",
     "materials[0].viscosity = 0.001 gives water its own dynamic viscosity (Hu & Adams): give either physics.nu or "
     "the materials' viscosity, not both"),
    ("viscosity = 1.8e-5\nbackground_pressure = 100.0", "viscosity = 1.8e-5\nbackground_pressure = 50.0",
     "materials[1].background_pressure", "50.0", "differs from materials[0]'s (water: 100 Pa)"),
    ('[[fluid]]\nbox = [[0.0, 0.25], [0.5, 0.5]]\nmaterial = "air"\n', "", "physics.surface_tension", "0.0728",
     "materials[1] (air) is used by no [[fluid]] block"),
]


@pytest.mark.parametrize("old, new, key, value, problem", BAD, ids=[f"{m[2]}={m[3]}" for m in BAD])
def test_bad_phase_values_are_refused_with_the_key_and_the_value(tmp_path, old, new, key, value, problem):
    assert old in TWO
    path = scene_file(tmp_path, TWO.replace(old, new))
    with pytest.raises(SceneFileError, match=re.escape(f"{path}: {key} = {value}: ") + ".*" + re.escape(problem)):
        read(path)


def test_dfsph_refuses_the_phase_terms_naming_their_keys(tmp_path):
    dfsph = ONE.replace('solver = "wcsph"', 'solver = "dfsph"')
    path = scene_file(tmp_path, dfsph.replace("surface_tension = 0.0728", ""))
    with pytest.raises(SceneFileError, match=re.escape(f"{path}: materials[0].viscosity = 0.001: the scene it makes "
                                                       "is refused: ") + ".*'phase_viscosity'"):
        load(path)
    path = scene_file(tmp_path, dfsph.replace("viscosity = 1e-3", ""))
    with pytest.raises(SceneFileError, match=re.escape(f"{path}: physics.surface_tension = 0.0728: the scene it "
                                                       "makes is refused: ") + ".*'surface_tension'"):
        load(path)


def test_two_phases_with_dummy_walls_validate_and_run(tmp_path):
    scene, _ = load(scene_file(tmp_path))
    scene.validate()
    sim = taisph.Simulation(scene)
    sim.step(5)
    assert sim.steps == 5 and sim.time > 0
    for values in (sim.positions(), sim.velocities(), sim.density(), sim.pressure()):
        assert np.all(np.isfinite(values))
    fluid = sim.kinds() == taisph.FLUID
    material, density, pressure = sim.materials()[fluid], sim.density()[fluid], sim.pressure()[fluid]
    # layers at rest: each phase's density within 1 % of its rho0, the pressure the background pressure plus at
    # most the water's weight (1000 * 9.81 * 0.25 = 2450 Pa), speeds far below the sound speeds (measured: 0.04
    # m/s at most, the air beside the walls at the interface)
    assert np.all(np.abs(density[material == 0] / 1000.0 - 1.0) < 0.01)
    assert np.all(np.abs(density[material == 1] / 1.2 - 1.0) < 0.01)
    assert np.all((pressure > 99.0) & (pressure < 100.0 + 2450.0))
    assert np.max(np.linalg.norm(sim.velocities(), axis=1)) < 0.1


def test_one_liquid_with_surface_tension_and_viscosity_runs(tmp_path):
    """The free-surface form and the viscosity of one material, with the default (Riemann) formulation."""
    scene, _ = load(scene_file(tmp_path, ONE))
    assert "riemann" in scene.terms_by_name
    sim = taisph.Simulation(scene)
    sim.step(5)
    for values in (sim.positions(), sim.velocities(), sim.density(), sim.pressure()):
        assert np.all(np.isfinite(values))
    assert np.max(np.linalg.norm(sim.velocities(), axis=1)) < 0.1


def test_set_on_the_command_line_reaches_the_phase_terms(tmp_path, capsys):
    """``--set sigma=...`` sets physics.surface_tension, ``--set viscosity=...`` every material's (as Scene.set
    sets every material's constant); the file keys themselves work too."""
    path = scene_file(tmp_path)
    scene, _ = load(path, {"sigma": 0.05, "viscosity": 2e-3, "background_pressure": 10.0})
    assert scene.terms_by_name["surface_tension"].values["sigma"] == 0.05
    assert [m.viscosity for m in scene.materials] == [2e-3, 2e-3]
    assert [m.background_pressure for m in scene.materials] == [10.0, 10.0]
    scene, _ = load(path, {"physics.surface_tension": 0.02, "materials[1].viscosity": 0.0})
    assert scene.terms_by_name["surface_tension"].values["sigma"] == 0.02
    assert [m.viscosity for m in scene.materials] == [1e-3, 0.0]
    # a file without [[materials]]: its one material, water
    plain = ONE.replace('[[materials]]\nname = "water"\nviscosity = 1e-3\n', "")
    scene, _ = load(scene_file(tmp_path, plain, "plain.toml"), {"viscosity": 1e-3})
    assert scene.materials[0].name == "water" and scene.materials[0].viscosity == 1e-3
    # the command line: a bad value refused, naming the key it set, before anything is written
    out = tmp_path / "out"
    assert cli([str(path), "--out", str(out), "--no-progress", "--set", "sigma=-1"]) == 2
    assert f"{path}: physics.surface_tension = -1: must be in [0, 1000]" in capsys.readouterr().err
    assert cli([str(path), "--out", str(out), "--no-progress", "--set", "viscosity=-1"]) == 2
    assert f"{path}: materials[0].viscosity = -1: must be in [0, 1e+06]" in capsys.readouterr().err
    assert not out.exists()


def test_the_documented_two_phase_example_builds(tmp_path):
    """docs/scenes.md's two-phase scene file (its [[materials]] section) is a valid file with the terms it names."""
    from pathlib import Path

    page = (Path(__file__).resolve().parent.parent / "docs" / "scenes.md").read_text()
    block = re.search(r'```toml\n(name = "water_under_air"\n.*?)```', page, re.S)
    assert block, "the two-phase example is gone from docs/scenes.md"
    scene, settings = load(scene_file(tmp_path, block[1], "water_under_air.toml"))
    assert [(m.name, m.viscosity, m.background_pressure) for m in scene.materials] == [
        ("water", 1e-3, 1000.0), ("air", 1.8e-5, 1000.0)]
    assert set(scene.terms_by_name) == {"continuity_colagrossi", "pressure_hu_adams", "phase_viscosity",
                                        "surface_tension", "gravity", "dummy_walls"}
    for line in settings.notes:  # the header lines the page quotes
        assert f"  {line}\n" in page.split(block[0])[1]
