"""A probe inside a wall or an obstacle is refused before anything runs (issue 50: it was
accepted and read nan all run), with a message naming the probe, its point, the wall and
where the probe came from; a probe in empty air (the fluid may come) or on the fluid's
side of a wall, on its face or in a corner, is not. The rule (taisph.probes.check_placement):
the walls' material (the cubes of side dx around their particles) fills at least 90 % of
the point's kernel support, or no fluid can come within 1.25 dx of it (the outer layers of
a tank's wall), or it lies in a hollow of the walls the fluid cannot reach (inside a
cylinder of wall rings)."""

import numpy as np
import pytest

import taisph
from taisph.engine.layout import WALL
from taisph.formats.scenefile import load
from taisph.probes import InsideWallError, Probes, check_inside, check_placement, flow, pressure
from taisph.scene import catalogue


@pytest.fixture(scope="module")
def tank():
    """The dam break at dx = 0.1: a 4 m x 4 m tank, walls of 3 layers (x < 0, y < 0, x > 4),
    the water in 0 < x < 1, 0 < y < 2; its command line names all its walls "walls"."""
    scene = taisph.cases.dam_break(dx=0.1)
    return scene, {"walls": np.flatnonzero(scene.kind == WALL)}


@pytest.mark.parametrize("at, what", [((-0.15, 0.3), "the left wall"), ((0.3, -0.15), "the floor, under the water"),
                                      ((4.15, 0.3), "the right wall, away from the water"),
                                      ((-0.2, -0.2), "the corner of the walls"),
                                      ((-0.25, 0.3), "the left wall's outer layer"),
                                      ((4.28, 0.3), "the right wall's outer layer, by its outer face")])
def test_a_point_inside_a_wall_is_refused_naming_it(tank, at, what):
    scene, walls = tank
    with pytest.raises(InsideWallError) as info:
        check_inside([pressure("in", at)], scene.domain, "--probe", scene=scene, walls=walls)  # what the CLI calls
    message = str(info.value)
    assert message.startswith(f"--probe: probe 'in': at = {at!r} lies inside the walls ("), message
    assert "so it would read nan all run; move it to the fluid's side of the wall" in message and "\n" not in message
    assert isinstance(info.value, ValueError) and info.value.probe == "in" and info.value.wall == "walls"


@pytest.mark.parametrize("at, what", [((1.5, 1.5), "empty air above the floor, no particle near"),
                                      ((0.05, 0.3), "in the water against the left wall"),
                                      ((0.0, 0.3), "on the left wall's face, in the water"),
                                      ((0.0, 0.0), "in the water's corner"),
                                      ((4.0, 0.3), "on the right wall's face, dry at the start"),
                                      ((4.0, 0.0), "in the dry corner"),
                                      ((2.0, 0.05), "just above the dry floor"),
                                      ((-0.05, 0.3), "in the wall's first layer, against the water")])
def test_a_point_on_the_fluids_side_or_in_air_is_accepted(tank, at, what):
    scene, walls = tank
    check_inside([pressure("ok", at)], scene.domain, "--probe", scene=scene, walls=walls)


def test_faces_are_refused_only_when_all_inside(tank):
    """A sensor's face or a flow face wholly inside a wall is refused (a flow's would read
    no flow); one reaching the fluid's side is not."""
    scene, walls = tank
    with pytest.raises(InsideWallError, match=r"^probe 'F': its face from at = \(-0.2, 0.1\) to to = \(-0.2, 0.5\) "
                                              r"lies inside the walls .* read nan all run"):
        check_placement([pressure("F", (-0.2, 0.1), to=(-0.2, 0.5))], scene, walls)
    with pytest.raises(InsideWallError, match=r"^probe 'Q': .* so it would read no flow all run"):
        check_placement([flow("Q", (-0.25, 0.1), (-0.15, 0.1))], scene, walls)
    check_placement([pressure("F", (-0.2, 0.1), to=(0.2, 0.1)), flow("Q", (-0.1, 0.5), (0.5, 0.5))], scene, walls)


def test_a_point_inside_a_hollow_obstacle_is_refused():
    """The cylinder's body is rings of wall particles around a hollow: its centre has no
    particle within a kernel support, yet no fluid can ever reach it. Its surface points
    (the case's own p_front, p_back) pass."""
    scene = taisph.cases.cylinder()
    walls = {"walls": np.flatnonzero(scene.kind == WALL), **scene.wall_groups}
    ring = scene.position[scene.wall_groups["cylinder"]]
    centre = tuple(float(v) for v in (ring.min(axis=0) + ring.max(axis=0)) / 2)
    with pytest.raises(InsideWallError, match=r"^--probe: probe 'c': at = .* lies inside the wall 'cylinder' \(in a "
                                              r"hollow the walls close off from the fluid\)"):
        check_inside([pressure("c", centre)], scene.domain, "--probe", scene=scene, walls=walls)
    check_placement(scene.probes, scene, walls)


def test_a_scene_files_probe_names_its_key(tmp_path):
    """The scene file's key as the source; without groups, the particle nearest to it."""
    scene, settings = load(catalogue.find_scene_file("dam_break_probes_2d.toml"))
    check_placement(settings.probes, scene, settings.wall_groups)  # its own: on the walls' faces, in the air
    probes = list(settings.probes) + [pressure("deep", (3.26, 0.3))]
    sources = [f"tank.toml: probes[{k}]" for k in range(len(probes))]
    with pytest.raises(InsideWallError, match=r"^tank.toml: probes\[7\]: probe 'deep': at = \(3.26, 0.3\) lies "
                                              r"inside the wall 'tank' \(the walls fill 9\d %"):
        check_inside(probes, scene.domain, sources, scene=scene, walls=settings.wall_groups)
    with pytest.raises(InsideWallError, match=r"^probe 'deep': at = \(3.26, 0.3\) lies inside a wall \(the wall "
                                              r"particle nearest to it at \(3\.2\d+, 0\.\d+\); the walls fill"):
        check_placement(probes[-1:], scene)


def test_the_shipped_cases_and_scene_files_probes_pass():
    for name in ("cylinder", "floating_box", "solitary_wave", "water_entry", "wave_flume"):
        scene = catalogue.find(name)()
        check_placement(scene.probes, scene)
    for path in catalogue.scene_files():
        scene, settings = load(path)
        check_placement(settings.probes, scene, settings.wall_groups)


def test_the_writer_refuses_it_before_anything_is_written(tmp_path, tank):
    """From Python: Probes refuses it when the run starts, no step taken, no file."""
    scene, _ = tank
    sim = taisph.Simulation(scene)
    path = tmp_path / "probes.csv"
    with pytest.raises(InsideWallError, match=r"^probe 'in': at = \(-0.15, 0.3\) lies inside a wall"):
        sim.run(0.01, frames=1, writers=[Probes([pressure("ok", (0.5, 0.5)), pressure("in", (-0.15, 0.3))],
                                                path=path)])
    assert sim.steps == 0 and not path.exists()
    sim.close()


def test_walls_of_finer_particles_on_their_nominal_face_pass():
    """The seed's wedge case has one line of wall particles dx/2 apart on the tank's faces
    and the wedge's: points on those lines (the fluid dx/2 away) read the fluid and pass;
    counting the particles' volumes m/rho there would make the walls fill 105 %."""
    scene = taisph.cases.dam_break_wedge()
    check_placement([pressure(f"p{k}", at) for k, at in enumerate([(0.0, 0.3), (0.0, 0.0), (3.0, 0.0), (2.7, 0.3)])],
                    scene)


def test_the_command_line_refuses_it_before_compiling_or_writing(tmp_path, capsys):
    """--probe in a wall and a scene file's probe in a wall: exit 2, one line naming the
    probe, nothing written (the check ran only when the run began, after the kernels
    compiled and frame 0 was written)."""
    from taisph.cli.main import main as cli

    out = tmp_path / "case"
    assert cli(["dam_break", "--dx", "0.1", "--probe", "pressure:in:-0.15,0.5", "--out", str(out),
                "--no-progress"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("taisph: error: --probe") and "'in'" in err[0], err
    assert not out.exists()
    text = catalogue.find_scene_file("dam_break_probes_2d.toml").read_text()
    path = tmp_path / "walled.toml"
    path.write_text(text + '\n[[probes]]\nname = "deep"\nkind = "pressure"\nat = [3.26, 0.3]\n')
    out = tmp_path / "file"
    assert cli([str(path), "--t-end", "0.001", "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and f"{path}: probes[" in err[0] and "'deep'" in err[0], err
    assert not out.exists()
