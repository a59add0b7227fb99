"""Body probes: the state of a moving or floating body (``Simulation.bodies()``) in
probes.csv, its columns named exactly ``NAME_x, NAME_y, NAME_angle, NAME_vx, NAME_vy,
NAME_omega, NAME_fx, NAME_fy`` (2D) and ``NAME_x ... NAME_qw ... NAME_wz, NAME_fx ...``
(3D); a body drifting at constant velocity reads x0 + v t to round-off; the probe agrees
with a force probe on the body's wall group; a body the scene does not have is refused,
naming the probe and the body, before anything is written."""

import numpy as np
import pytest

import taisph
from taisph.formats.scenefile import load
from taisph.geometry.shapes import lattice
from taisph.messages import InputError
from taisph.probes import BODY_COLUMNS, Probe, Probes, body, force, parse, read_csv
from taisph.run.checkpoint import probe_from_data, probe_to_data
from taisph.scene.catalogue import cases_folder
from taisph.terms import AdamiWall, Continuity, PressureGradient

COLUMNS_2D = ["box_x", "box_y", "box_angle", "box_vx", "box_vy", "box_omega", "box_fx", "box_fy"]
COLUMNS_3D = ["box_x", "box_y", "box_z", "box_qw", "box_qx", "box_qy", "box_qz", "box_vx", "box_vy", "box_vz",
              "box_wx", "box_wy", "box_wz", "box_fx", "box_fy", "box_fz"]


def drifting_box(dim, dx=0.02):
    """A floating box alone (no fluid, no gravity) starting at velocity (1, 0(, 0))."""
    lo, hi = (-0.1, -0.05, -0.05)[:dim], (0.1, 0.05, 0.05)[:dim]
    scene = taisph.Scene(name="drift", dim=dim, dx=dx, smoothing_length=1.3 * dx, domain=((-0.5,) * dim, (0.5,) * dim),
                         terms=[PressureGradient(walls=True), Continuity(walls=True), AdamiWall()], t_end=0.1)
    scene.add_body("box", lattice(lo, hi, dx), density=500, velocity=(1.0,) + (0.0,) * (dim - 1))
    return scene


@pytest.mark.parametrize("dim", [2, 3])
def test_a_drifting_body_reads_x0_plus_vt_in_exactly_named_columns(dim, tmp_path):
    scene = drifting_box(dim, dx=0.02 if dim == 2 else 0.05)
    x0 = scene.bodies[0].centre.copy()
    sim = taisph.Simulation(scene, dt=1e-3)
    probes = Probes([body("box")], path=tmp_path / "probes.csv")
    sim.run(0.1, frames=1, writers=[probes])
    probes.close()
    expected = COLUMNS_2D if dim == 2 else COLUMNS_3D
    assert probes.columns() == expected == Probe("box", "body").columns(dim)
    data = read_csv(tmp_path / "probes.csv")  # (10 significant digits)
    assert list(data) == ["time", *expected]
    t, values = probes.times, probes.values["box"]  # (N, columns), as a force probe's (N, dim)
    assert values.shape == (len(t), len(expected)) == (sim.steps + 1, len(expected))
    assert t[0] == 0.0 and abs(t[-1] - 0.1) < 1e-12 and np.allclose(data["time"], t, rtol=1e-15, atol=0)
    for k, name in enumerate(expected):
        assert np.allclose(data[name], values[:, k], rtol=1e-9, atol=1e-300), name
    column = dict(zip(expected, values.T))
    assert np.max(np.abs(column["box_x"] - (x0[0] + t))) < 1e-12  # x0 + v t: after 0.1 s, x0 + 0.1
    assert abs(column["box_x"][-1] - (x0[0] + 0.1)) < 1e-12
    assert np.all(column["box_vx"] == 1.0) and np.all(column["box_y"] == x0[1])
    assert np.all(column["box_fx"] == 0.0)  # no fluid: no force
    if dim == 2:
        assert np.all(column["box_angle"] == 0.0) and np.all(column["box_omega"] == 0.0)
    else:
        assert np.all(column["box_qw"] == 1.0) and np.all(column["box_qx"] == 0.0) and np.all(column["box_wz"] == 0.0)
    times, own = probes.series("box")
    assert np.array_equal(times, t) and np.array_equal(own, values)
    state = sim.bodies()["box"]
    assert np.allclose(values[-1, :dim], state.position, rtol=0, atol=1e-15)
    sim.close()


def test_a_body_probe_agrees_with_a_force_probe_on_the_bodys_wall_group():
    """The floating box of cases/floating_box_2d.toml (at dx = 0.05 m): its probe's force is
    the fluid's force on its particles, the force probe's on its wall group (the same pair
    terms; no contact in still water), and its centre stays at (1, 1) within a millimetre."""
    scene, settings = load(cases_folder() / "floating_box_2d.toml", {"dx": 0.05})
    probes = Probes([*settings.probes, force("box_force", "box", every=10)], walls=settings.wall_groups)
    sim = taisph.Simulation(scene)
    sim.run(0.05, frames=1, writers=[probes])
    times, box = probes.series("box")
    _, pushed = probes.series("box_force")
    assert len(times) >= 3 and box.shape[1] == 8
    assert np.allclose(box[:, 6:], pushed, rtol=1e-9, atol=1e-9 * 125 * 9.81)  # (measured: equal to the bit)
    assert np.all(np.abs(box[:, :2] - 1.0) < 1e-3)
    assert abs(box[-1, 7] / (125 * 9.81) - 1) < 0.05  # the water carries the box's weight
    sim.close()


def test_a_body_the_scene_does_not_have_is_refused_before_anything_is_written(tmp_path):
    sim = taisph.Simulation(drifting_box(2, dx=0.05), dt=1e-3)
    path = tmp_path / "probes.csv"
    with pytest.raises(InputError, match=r"probe 'lid': no body 'lid'; the scene's bodies: box"):
        sim.run(0.01, frames=1, writers=[Probes([body("lid")], path=path)])
    with pytest.raises(InputError, match=r"probe 'b': no body 'boat'; the scene's bodies: box"):
        sim.run(0.01, frames=1, writers=[Probes([Probe("b", "body", body="boat")], path=path)])
    assert not path.exists() and sim.steps == 0
    sim.close()
    still = taisph.Simulation(taisph.cases.hydrostatic_tank(dx=0.1))
    with pytest.raises(InputError, match=r"probe 'box': no body 'box'; the scene's bodies: none"):
        still.run(0.01, frames=1, writers=[Probes([body("box")])])
    still.close()


def test_the_command_line_syntax_and_checkpoints_know_body_probes():
    probe = parse("body:boat:box:10", 2)
    assert (probe.kind, probe.name, probe.target, probe.every) == ("body", "boat", "box", 10)
    assert probe.columns(2) == [f"boat_{c}" for c in BODY_COLUMNS[2]]
    assert probe_from_data(probe_to_data(probe)) == probe
    assert probe_from_data(probe_to_data(body("box"))).target == "box"  # body defaults to the probe's name
    old = {k: v for k, v in probe_to_data(force("F", "walls")).items() if k != "body"}  # a checkpoint before bodies
    assert probe_from_data(old) == force("F", "walls")
    with pytest.raises(InputError, match="body = ''"):
        Probe("b", "body", body="").check(2)
