"""probes.csv says what each column measures (issue 50): beside it, probes.json lists every
column, in the CSV's order, with its probe, kind, quantity and unit (pressure Pa, surface
elevation m, force N, flow rate m^2/s in 2D and m^3/s in 3D, a body's position m,
orientation rad (2D) or 1 (3D quaternion), velocity m/s, angular velocity rad/s, force N).
The CSV itself stays plain (a header line, then numbers), so numpy, pandas and the csv
module read it as before. Before, the header named the columns only: a plot could not
tell a pressure from a flow rate."""

import json

import numpy as np
import pytest

import taisph
from taisph.engine.layout import WALL
from taisph.probes import BODY_COLUMNS, Probe, Probes, body, elevation, flow, force, pressure, read_csv, read_units


def test_each_kind_has_its_quantity_and_unit():
    assert pressure("P", (0, 0)).units(2) == [("P", "pressure", "Pa")]
    assert elevation("H", 0.5).units(2) == [("H", "surface elevation", "m")]
    assert force("F", "walls").units(3) == [("F_x", "force", "N"), ("F_y", "force", "N"), ("F_z", "force", "N")]
    assert flow("Q", (1, 0), (1, 1)).units(2) == [("Q", "flow rate", "m^2/s")]
    assert flow("Q", (1, 0, 0), (1, 1, 1)).units(3) == [("Q", "flow rate", "m^3/s")]
    units = {c: (q, u) for c, q, u in body("b").units(2)}
    assert list(units) == [f"b_{c}" for c in BODY_COLUMNS[2]]
    assert (units["b_x"], units["b_angle"], units["b_vy"], units["b_omega"], units["b_fx"]) == (
        ("body position", "m"), ("body orientation", "rad"), ("body velocity", "m/s"),
        ("body angular velocity", "rad/s"), ("body force", "N"))
    units = {c: (q, u) for c, q, u in Probe("c", "body", body="boat").units(3)}
    assert list(units) == [f"c_{c}" for c in BODY_COLUMNS[3]]
    assert (units["c_qw"], units["c_wz"], units["c_fz"]) == (("body orientation", "1"),
                                                             ("body angular velocity", "rad/s"), ("body force", "N"))


def test_the_sidecar_names_every_column_of_the_csv_with_its_unit(tmp_path):
    """A floating box's body probe and wave gauge with a pressure, a flow and a force
    probe, a few steps: probes.json's columns are the CSV's header, each with its unit."""
    scene = taisph.cases.floating_box(dx=0.05)
    sim = taisph.Simulation(scene)
    floor = np.flatnonzero((scene.kind == WALL) & (scene.position[:, 1] < 0))
    path = tmp_path / "out" / "probes.csv"
    probes = Probes(list(scene.probes) + [pressure("P", (0.2, 0.2)), flow("Q", (0.2, 0.0), (0.2, 0.5)),
                                          force("floor", "floor")], walls={"floor": floor}, path=path)
    try:
        sim.run(3 * sim.dt, frames=1, writers=[probes])
    finally:
        probes.close()
        sim.close()
    header = path.read_text().splitlines()[0].split(",")
    units = read_units(path)
    assert list(units) == header
    assert units["time"] == {"probe": None, "kind": "time", "quantity": "time", "unit": "s"}
    assert units["P"] == {"probe": "P", "kind": "pressure", "quantity": "pressure", "unit": "Pa"}
    assert units["gauge"]["unit"] == "m" and units["Q"]["unit"] == "m^2/s"
    assert units["floor_y"] == {"probe": "floor", "kind": "force", "quantity": "force", "unit": "N"}
    assert (units["box_angle"]["unit"], units["box_vx"]["unit"], units["box_fy"]["unit"]) == ("rad", "m/s", "N")
    data = json.loads((tmp_path / "out" / "probes.json").read_text())
    assert data["format"] == "taisph probes 1" and data["dim"] == 2 and data["csv"] == "probes.csv"
    assert [p["name"] for p in data["probes"]] == ["box", "gauge", "P", "Q", "floor"]
    assert data["probes"][3] == {"name": "Q", "kind": "flow", "every": 1, "at": [0.2, 0.0], "to": [0.2, 0.5]}
    assert sorted(p.name for p in path.parent.iterdir()) == ["probes.csv", "probes.json"]  # no temporary file
    table = np.genfromtxt(path, delimiter=",", names=True)  # the CSV stays plain: numpy reads it with its header
    assert list(table.dtype.names) == [c.replace(".", "") for c in header] and len(table) == len(read_csv(path)["time"])


def test_a_csv_without_sidecar_or_with_comment_lines_still_reads(tmp_path):
    """An older run's CSV has no sidecar: read_units says None; '#' lines are comments."""
    path = tmp_path / "probes.csv"
    path.write_text("# columns: time (s); P: pressure, Pa\ntime,P\n0.0,1.5\n# a note\n0.1,\n")
    assert read_units(path) is None
    data = read_csv(path)
    assert list(data) == ["time", "P"] and data["time"].tolist() == [0.0, 0.1]
    assert data["P"][0] == 1.5 and np.isnan(data["P"][1])
    (tmp_path / "probes.json").write_text("{not json")
    with pytest.raises(ValueError, match=r"probes.json: not a probes sidecar"):
        read_units(path)
