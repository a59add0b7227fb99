"""``[[bodies]]`` in scene files: cases/floating_box_2d.toml builds one floating box of
125 kg/m set up at its equilibrium draft, on the water's lattice with no water inside it; a
prescribed body follows a trajectory file or a wave maker; every mistake (a missing
name, density and mass both, a bad motion, a trajectory file missing, unreadable or
going back in time, an unknown wave maker, a body overlapping the water, a body probe
naming no body...) is refused naming the file, the key and the value, before anything
is built or written."""

import re

import numpy as np
import pytest

import taisph
from taisph.cli.main import main as cli
from taisph.formats.scenefile import load
from taisph.formats.scenefile_spec import SceneFileError
from taisph.probes import read_csv
from taisph.scene.catalogue import cases_folder

RHO0 = 1000.0

# a small tank of water (dx = 0.05 m) with a floating box above its surface at y = 0.3 m
BASE = """\
name = "bodies"
dim = 2
dx = 0.05
t_end = 0.05
frames = 1

[[fluid]]
box = [[0.0, 0.0], [1.0, 0.3]]

[[walls]]
name = "tank"
box = [[0.0, 0.0], [1.0, 0.8]]

[[bodies]]
name = "box"
box = [[0.4, 0.4], [0.6, 0.5]]
density = 500.0

{extra}
[[probes]]
name = "box"
kind = "body"
{probe}
"""


def scene_file(tmp_path, body="", extra="", probe="", base=BASE):
    text = base.format(extra=extra, probe=probe)
    if body:  # replace the first body's keys (after its name, up to the next block)
        head, tail = text.split('name = "box"\n', 1)
        text = head + 'name = "box"\n' + body + "\n" + tail[tail.index("\n[["):].lstrip("\n")
    path = tmp_path / "bodies.toml"
    path.write_text(text)
    return path


def test_the_floating_box_example_is_set_up_at_its_equilibrium_draft():
    """cases/floating_box_2d.toml: one floating body of 500 x 0.25 = 125 kg/m, a 0.5 m x 0.5 m
    box centred in the 2 m tank with its bottom at 0.75 m, in water 1 m deep: it is set up at
    a draft of 0.25 m, mass / (rho0 width) (where Archimedes puts it; this checks the scene as
    built, nothing is run: that it floats there is tests/test_bodies.py's); its particles
    continue the water's lattice (dx apart from the nearest water particles) and no water lies
    inside it."""
    scene, settings = load(cases_folder() / "floating_box_2d.toml")
    dx = scene.dx
    assert [(b.name, b.motion) for b in scene.bodies] == [("box", "floating")]
    box = scene.bodies[0]
    assert abs(box.mass / (500 * 0.25) - 1) < 0.01
    x = scene.position[box.ids]
    lo, hi = x.min(axis=0) - dx / 2, x.max(axis=0) + dx / 2  # the faces of its cells
    assert np.allclose(lo, [0.75, 0.75], atol=1e-12) and np.allclose(hi, [1.25, 1.25], atol=1e-12)
    assert np.allclose(box.centre, [1.0, 1.0], atol=1e-12)
    assert len(box.ids) == round(0.5 / dx) ** 2 and np.all(scene.kind[box.ids] == taisph.WALL)
    water = scene.position[scene.kind == taisph.FLUID]
    surface = water[:, 1].max() + dx / 2
    assert abs(surface - 1.0) < 1e-12 and abs(water[:, 0].min() - dx / 2) < 1e-12 and abs(water[:, 0].max() - 2 + dx / 2) < 1e-12
    draft = surface - lo[1]
    assert abs(draft - 0.25) < 1e-12 and abs(draft - box.mass / (RHO0 * (hi[0] - lo[0]))) < 0.01 * draft
    inside = np.all((water > lo) & (water < hi), axis=1)
    assert not inside.any()
    gaps = np.linalg.norm(water[:, None, :] - x[None, :, :], axis=2).min()
    assert abs(gaps - dx) < 1e-9  # the same lattice: the nearest water particle dx from the box
    assert len(water) == round(2 / dx) * round(1 / dx) - round(0.5 / dx) * round(0.25 / dx)
    assert "dummy_walls" in scene.terms_by_name and "rigid_bodies" in scene.terms_by_name
    assert np.array_equal(np.arange(scene.n)[settings.wall_groups["box"]], box.ids)
    probes = {p.name: p for p in settings.probes}
    assert (probes["box"].kind, probes["box"].target, probes["box"].every) == ("body", "box", 10)
    assert (probes["gauge"].kind, probes["gauge"].at) == ("elevation", (0.3,))
    assert (settings.t_end, scene.dx) == (2.0, 0.025)


def test_a_prescribed_body_follows_its_trajectory_file(tmp_path):
    """A lid lifted along a CSV table (t, x, y, angle): its probe reads the table's pose,
    interpolated, and its velocity, 0.05 m / 0.1 s, at every sample to the run's end."""
    (tmp_path / "lift.csv").write_text("# a lift\nt, x, y, angle\n0.0, 0.0, 0.0, 0.0\n0.1, 0.0, 0.05, 0.0\n")
    path = scene_file(tmp_path, body='box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ntrajectory = "lift.csv"\n'
                      'until = 0.1')  # (tabulated to t = 0.1 s, past the run's end: still moving at its end)
    scene, settings = load(path)
    (lid,) = scene.bodies
    assert lid.motion == "prescribed" and "table of 2 rows" in lid.trajectory
    out = tmp_path / "out"
    assert cli([str(path), "--out", str(out), "--no-progress"]) == 0
    data = read_csv(out / "probes.csv")
    assert abs(data["time"][-1] - 0.05) < 1e-12
    assert np.allclose(data["box_y"], 0.45 + 0.5 * data["time"], rtol=0, atol=1e-9)
    assert np.allclose(data["box_vy"], 0.5, rtol=1e-6) and abs(data["box_y"][-1] - 0.475) < 1e-9
    assert np.all(data["box_x"] == 0.5)


@pytest.mark.parametrize("maker,keys", [("piston", "height = 0.02\nperiod = 1.0\ndepth = 0.3\naxis = [1.0, 0.0]"),
                                        ("solitary", "height = 0.05\ndepth = 0.3"),
                                        ("flap", "height = 0.02\nperiod = 1.0\ndepth = 0.3\ncentre = [0.5, 0.4]\nramp = 1.0")])
def test_a_wave_maker_body(tmp_path, maker, keys):
    """wave_maker = "piston", "solitary" or "flap" with its parameters: the body's motion is
    taisph.scene.wave_makers' (its description in the run's header)."""
    body = f'box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\nwave_maker = "{maker}"\n{keys}\n'
    scene, _ = load(scene_file(tmp_path, body=body, base=BASE.replace("t_end = 0.05", "t_end = 2.0")))
    (paddle,) = scene.bodies
    assert paddle.motion == "prescribed" and paddle.trajectory.startswith(maker if maker != "solitary" else "piston")
    assert ("solitary" in paddle.trajectory) == (maker == "solitary")
    assert f"body box: 8 particles, prescribed ({maker if maker != 'solitary' else 'piston'}" in scene.describe()


# (body keys, extra blocks, probe keys) -> the key and the words of the refusal
MISTAKES = [
    ("box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0", "", "", None),  # the base, accepted
    ("", '[[bodies]]\nname = "second"\nbox = [[0.7, 0.4], [0.8, 0.5]]\nmass = 1.0\n', "", None),
    ("", "", 'body = "lid"', r"probes\[0\]\.body = 'lid': no body of that name; bodies: box"),
    ("", "", 'walls = "box"', r"probes\[0\]\.walls = 'box': a body probe takes body, not walls"),
    (None, "", "", r"bodies\[0\]\.name = \(missing\): required"),
    ("box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nmass = 5.0", "", "",
     r"bodies\[0\]\.mass = 5\.0: give its density or its mass, not both"),
    ("box = [[0.4, 0.4], [0.6, 0.5]]", "", "", r"bodies\[0\]\.density = \(missing\): a floating body needs its density"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nmotion = "sinking"', "", "",
     r"bodies\[0\]\.motion = 'sinking': must be one of 'prescribed', 'floating'"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ntrajectory = "nope.csv"', "", "",
     r"bodies\[0\]\.trajectory = 'nope.csv': .*nope\.csv: no such trajectory file"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ntrajectory = "back.csv"', "", "",
     r"bodies\[0\]\.trajectory = 'back.csv': .*back\.csv, line 4 \(row 3\): t = 0\.05 s: the times must increase "
     r"\(line 3 has t = 0\.1 s\)"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ntrajectory = "words.csv"', "", "",
     r"bodies\[0\]\.trajectory = 'words.csv': .*words\.csv, line 3: '0\.1, up, 0, 0': not a number"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ntrajectory = "headless.csv"', "", "",
     r"bodies\[0\]\.trajectory = 'headless.csv': .*headless\.csv, line 1: '0, 0, 0, 0': expected the header t, x, y, angle"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\nwave_maker = "paddle"', "", "",
     r"bodies\[0\]\.wave_maker = 'paddle': must be one of 'piston', 'flap', 'solitary'"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\nwave_maker = "piston"\nheight = 0.5\nperiod = 0.5\ndepth = 0.3',
     "", "", r"bodies\[0\]\.height = 0\.5: piston wave maker: height = 0\.5 m is too high"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\nwave_maker = "flap"\nheight = 0.02\nperiod = 1.0\ndepth = 0.3',
     "", "", r"bodies\[0\]\.centre = \(missing\): a flap turns about its hinge"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\nwave_maker = "solitary"\nheight = 0.05\ndepth = 0.3\nperiod = 1.0',
     "", "", r"bodies\[0\]\.period = 1\.0: a solitary wave maker takes height, depth, not period"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ndensity = 500.0\nwave_maker = "piston"', "", "",
     r"bodies\[0\]\.density = 500\.0: a prescribed body takes no density"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nwave_maker = "piston"', "", "",
     r"bodies\[0\]\.wave_maker = 'piston': a floating body takes no wave_maker"),
    ("box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nfixed = [\"x\", \"z\"]", "", "",
     r"bodies\[0\]\.fixed\[1\] = 'z': not a degree of freedom of a 2D body: x, y, rotation"),
    ("box = [[0.4, 0.4], [0.6, 0.5]]\npolygon = [[0, 0], [1, 0], [0, 1]]\ndensity = 500.0", "", "",
     r"bodies\[0\] = \{'box': .*'polygon': .*\}: give exactly one of box"),
    ("box = [[0.2, 0.1], [0.4, 0.2]]\ndensity = 500.0", "", "",
     r"bodies\[0\]\.box = \[\[0\.2, 0\.1\], \[0\.4, 0\.2\]\]: body 'box' overlaps the fluid at t = 0"),
    ("box = [[-0.2, 0.4], [0.1, 0.5]]\ndensity = 500.0", "", "",
     r"bodies\[0\]\.box = \[\[-0\.2, 0\.4\], \[0\.1, 0\.5\]\]: body 'box' overlaps the walls at t = 0"),
    ("box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\ninertia = -1.0", "", "", r"bodies\[0\]\.inertia = -1\.0: must be"),
    ("", '[[bodies]]\nname = "tank"\nbox = [[0.7, 0.4], [0.8, 0.5]]\nmass = 1.0\n', "",
     r"bodies\[1\]\.name = 'tank': already the name of a wall group"),    ("box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nhinge = [0.5, 0.4]\nfixed = [\"rotation\"]", "", "",
     r"bodies\[0\]\.box = .*: body 'box': a hinged body turns about its hinge: fixed must not hold its rotation"),
    ("box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nhinge = [0.5]", "", "", r"bodies\[0\]\.hinge = \[0\.5\]"),
    ('box = [[0.4, 0.4], [0.6, 0.5]]\nmotion = "prescribed"\ntrajectory = "back.csv"\nhinge = [0.5, 0.4]', "", "",
     r"bodies\[0\]\.hinge = \[0\.5, 0\.4\]: .*"),
]


def test_a_hinged_body_in_a_scene_file(tmp_path):
    """hinge = [x, y]: the body turns about that point, which becomes its reference point;
    its translations are held and its inertia is taken about the hinge (parallel axes)."""
    scene, _ = load(scene_file(tmp_path, body="box = [[0.4, 0.4], [0.6, 0.5]]\ndensity = 500.0\nhinge = [0.5, 0.4]"))
    (plate,) = scene.bodies
    free = plate.centre_of_mass
    assert np.allclose(plate.centre, [0.5, 0.4]) and np.allclose(free, [0.0, 0.05])
    assert set(plate.fixed) == {"x", "y"}
    mass = 500.0 * 0.2 * 0.1
    assert abs(plate.inertia - mass * (0.2**2 + 0.1**2) / 12 - mass * 0.05**2) < 1e-12
    assert "hinged at (0.5, 0.4)" in scene.describe()


@pytest.mark.parametrize("body,extra,probe,problem", MISTAKES)
def test_every_mistake_names_the_file_the_key_and_the_value(tmp_path, body, extra, probe, problem):
    (tmp_path / "back.csv").write_text("t, x, y, angle\n0.0, 0, 0, 0\n0.1, 0, 0.01, 0\n0.05, 0, 0.02, 0\n")
    (tmp_path / "words.csv").write_text("t,x,y,angle\n0, 0, 0, 0\n0.1, up, 0, 0\n")
    (tmp_path / "headless.csv").write_text("0, 0, 0, 0\n0.1, 0, 0, 0\n")
    if body is None:  # no name
        path = scene_file(tmp_path, extra=extra, probe=probe)
        path.write_text(path.read_text().replace('[[bodies]]\nname = "box"\n', "[[bodies]]\n"))
    else:
        path = scene_file(tmp_path, body=body, extra=extra, probe=probe)
    if problem is None:
        scene, _ = load(path)
        assert len(scene.bodies) == 1 + ("second" in extra)
        return
    with pytest.raises(SceneFileError) as err:
        load(path)
    message = str(err.value)
    assert message.startswith(f"{path}: "), message
    assert re.search(problem, message), message


def test_bodies_need_dummy_walls_and_the_command_line_refuses_before_writing(tmp_path, capsys):
    path = scene_file(tmp_path, extra="")
    path.write_text(path.read_text().replace('box = [[0.0, 0.0], [1.0, 0.8]]', 'box = [[0.0, 0.0], [1.0, 0.8]]\nmodel = "lj"'))
    with pytest.raises(SceneFileError, match=re.escape(f"{path}: bodies = ['box']: the scene it makes is refused: bodies "
                                                       "are dummy-wall particles")):
        load(path)
    path = scene_file(tmp_path)
    out = tmp_path / "out"
    assert cli([str(path), "--out", str(out), "--probe", "body:b:boat"]) == 2
    assert "--probe: probe 'b': no body 'boat'; the scene's bodies: box" in capsys.readouterr().err
    path.write_text(path.read_text().replace("density = 500.0", "density = 500.0\nvelocity = [1.0]"))
    assert cli([str(path), "--out", str(out)]) == 2
    assert f"{path}: bodies[0].velocity = [1.0]: expected a list of 2 numbers" in capsys.readouterr().err
    assert not out.exists()
