"""More bad input (issue 50, item 6): a truncated STL file is refused in one line naming
the file and what is wrong (and the scene file and key it came from, exit code 2), not
meshio's own message; ``sim.set(alpha=-1)`` is refused as the command line refuses
``--set alpha=-1``, for every runtime parameter, naming the parameter, the value and
the allowed range, and changing nothing."""

import shutil

import meshio
import numpy as np
import pytest

import taisph
from taisph.cli.main import main as cli
from taisph.geometry.mesh import MeshError, box_mesh, check_stl, load_surface
from taisph.messages import InputError
from taisph.scene import catalogue
from taisph.scene.parameters import RUNTIME, ParameterError, check_runtime
from taisph.scene.serialize import TERMS

OBSTACLE = catalogue.cases_folder() / "obstacle_kleefsman.stl"  # an ASCII STL, 12 facets


def binary_stl(path, triangles_kept=None):
    """A cube as a binary STL (12 triangles), cut after `triangles_kept` triangles and 20 bytes."""
    vertices, faces = box_mesh((0, 0, 0), (1, 1, 1))
    meshio.write(path, meshio.Mesh(vertices, [("triangle", faces)]), binary=True)
    if triangles_kept is not None:
        data = path.read_bytes()
        path.write_bytes(data[:84 + 50 * triangles_kept + 20])
    return path


def test_a_truncated_binary_stl_names_the_file_and_the_count(tmp_path):
    """Before: meshio's 'UnicodeDecodeError: ...' (or a hole count); now one line."""
    path = binary_stl(tmp_path / "cut.stl", triangles_kept=5)
    with pytest.raises(MeshError) as refused:
        load_surface(path)
    message = str(refused.value)
    assert message == (f"{path}: truncated: the 84-byte header says 12 triangles, the file has 5 and 20 bytes of "
                       "another (354 bytes of 684)")
    assert isinstance(refused.value, InputError) and "\n" not in message
    whole = binary_stl(tmp_path / "whole.stl")
    check_stl(whole)
    assert load_surface(whole).measure == pytest.approx(1.0)
    (tmp_path / "short.stl").write_bytes(whole.read_bytes()[:50])
    with pytest.raises(MeshError, match=r"short\.stl: truncated: 50 bytes, shorter than the 84-byte header"):
        load_surface(tmp_path / "short.stl")


def test_an_ascii_stl_cut_mid_facet_says_where(tmp_path):
    text = OBSTACLE.read_text()
    lines = text.splitlines(keepends=True)
    cut = tmp_path / "cut.stl"
    cut.write_text("".join(lines[:17]) + lines[17][:9])  # inside facet 3, mid-line
    with pytest.raises(MeshError, match=r"cut\.stl: truncated: the file ends inside facet 3 \(line 18: .*; "
                                        r"2 whole facets\)$"):
        load_surface(cut)
    cut.write_text(text.replace("endsolid", ""))
    with pytest.raises(MeshError, match=r"truncated: the file ends after facet 12 without 'endsolid'"):
        load_surface(cut)
    cut.write_text(text.replace("vertex", "vertex x", 1))
    with pytest.raises(MeshError, match=r"line 4 \(facet 1\): a vertex needs three numbers, got 'vertex x "):
        load_surface(cut)
    assert load_surface(OBSTACLE).measure > 0


@pytest.mark.parametrize("cut", ["binary", "ascii"])
def test_a_truncated_stl_in_a_scene_file_exits_2_naming_file_and_key(tmp_path, capsys, cut):
    """python -m taisph SCENE.toml whose [[walls]] mesh is cut short: exit code 2, one line
    naming the scene file, the key, the mesh file and what is wrong; nothing written."""
    scene = tmp_path / "obstacle.toml"
    shutil.copy(catalogue.cases_folder() / "dam_break_obstacle_3d.toml", scene)
    mesh = tmp_path / "obstacle_kleefsman.stl"
    if cut == "binary":
        binary_stl(mesh, triangles_kept=7)
    else:
        mesh.write_text(OBSTACLE.read_text()[:900])
    assert cli([str(scene), "--out", str(tmp_path / "out"), "--no-progress"]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"taisph: error: {scene}: walls[1].mesh = 'obstacle_kleefsman.stl': {mesh}: truncated:")
    assert not (tmp_path / "out").exists()


def test_sim_set_refuses_what_the_command_line_refuses():
    """sim.set(alpha=-1) raised nothing before (the command line's --set alpha=-1 is exit
    code 2): now a ParameterError naming alpha, -1 and [0, 2]; the simulation keeps its
    values. The range is the one the case's --set uses."""
    sim = taisph.Simulation(taisph.cases.hydrostatic_tank(dx=0.1, t_end=0.01))
    before = dict(sim.parameters())
    with pytest.raises(ParameterError, match=r"scene 'hydrostatic_tank': alpha must be in \[0, 2\], got -1$"):
        sim.set(alpha=-1)
    with pytest.raises(ParameterError, match=r"gravity must have every component in \[-1000, 1000\], "
                                             r"got \(0.0, -1000000.0\)"):
        sim.set(alpha=0.05, gravity=(0.0, -1e6))
    with pytest.raises(ParameterError, match=r"c0 must be in \(0, 100000\], got 1000000000.0"):
        sim.set(c0=1e9)
    with pytest.raises(ParameterError, match=r"material 'water': rho0 must be in \(0, 100000\], got 1000000.0"):
        sim.set_material(0, rho0=1e6)
    dt, courant = sim.controls.dt, sim.controls.courant
    with pytest.raises(ParameterError, match=r"simulation control: dt must be > 0, got -1"):
        sim.set(dt=-1, alpha=0.05)  # a control refused: the scene's alpha is not changed either
    with pytest.raises(ParameterError, match=r"courant must be in \(0, 1\], got 3"):
        sim.set(courant=3)
    assert (sim.controls.dt, sim.controls.courant) == (dt, courant)
    assert sim.parameters() == before and sim.scene.materials[0].rho0 == 1000.0
    assert RUNTIME["alpha"] is catalogue.parameters("hydrostatic_tank")["alpha"].range
    sim.set(alpha=0.05)
    assert sim.parameters()["alpha"] == 0.05
    sim.close()


def test_every_runtime_parameter_has_a_range_that_its_defaults_meet():
    """Every parameter of every term taisph ships is declared in RUNTIME, and every shipped
    case and scene file builds values inside those ranges (so set() refuses only what the
    cases never use)."""
    for name, cls in TERMS.items():
        missing = [k for k in cls.params if k not in RUNTIME]
        assert not missing, f"{name}: no runtime range for {missing}"
    scenes = [f() for f in catalogue.registry().values()]
    from taisph.formats.scenefile import load

    scenes += [load(path)[0] for path in catalogue.scene_files()]
    for scene in scenes:
        scene.validate()  # the terms fill in what they derive (shift_dx, lattice_ratio...)
        for term in scene.terms:
            for key, value in term.values.items():
                check_runtime(key, value, scene.name)
        for material in scene.materials:
            for key in ("rho0", "c0", "gamma"):
                if getattr(material, key) is not None:
                    check_runtime(key, getattr(material, key), scene.name)
    with pytest.raises(ParameterError, match=r"alpha must be in \[0, 2\], got 'high'"):
        check_runtime("alpha", "high")
    with pytest.raises(ParameterError, match=r"drain_lo must have every component in"):
        check_runtime("drain_lo", np.array([0.0, np.nan]))
