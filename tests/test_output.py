"""ParaView output: frames read back equal the state; the .pvd index lists every frame
with its time; the command line writes what --frames asks for."""

import numpy as np
import pytest

import taisph
from taisph.cli import main as cli
from taisph.run import vtk


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    sim = taisph.Simulation(taisph.cases.dam_break(dx=0.08))
    summary = sim.run(0.05, frames=2, out=out)
    return sim, summary, out


def test_frames_read_back_equal_state(small_run):
    import meshio

    sim, summary, out = small_run
    last = sorted(out.glob("dam_break_*.vtu"))[-1]
    mesh = meshio.read(last)
    fluid = sim.fluid
    x = sim.positions()[fluid]
    assert mesh.points.shape == (fluid.sum(), 3)
    np.testing.assert_array_equal(mesh.points[:, :2], x)
    np.testing.assert_array_equal(mesh.points[:, 2], 0.0)
    pd = mesh.point_data
    np.testing.assert_array_equal(pd["velocity"][:, :2], sim.velocities()[fluid])
    np.testing.assert_array_equal(pd["velocity"][:, 2], 0.0)
    for name, values in (("pressure", sim.pressure()), ("density", sim.density()), ("mass", sim.masses()),
                         ("id", sim.ids()), ("material", sim.materials())):
        np.testing.assert_array_equal(pd[name], values[fluid], err_msg=name)
    walls = meshio.read(out / "walls.vtu")
    np.testing.assert_array_equal(walls.points[:, :2], sim.positions()[sim.wall])
    assert not list(out.glob("*.tmp")), "temporary files left behind"


def test_pvd_lists_frames_with_times(small_run, at_output_times):
    sim, summary, out = small_run
    entries = vtk.read_pvd(out / "dam_break.pvd")
    fluid = [(t, f) for t, part, f in entries if part == 0]
    at_output_times([t for t, _ in fluid], [0.0, 0.025, 0.05])
    assert all((out / f).exists() for _, _, f in entries)
    assert summary.frames == 3
    # the blocks are named for ParaView (they were "Block 0", "Block 1": issue 50)
    import xml.etree.ElementTree as ET

    names = {(e.get("part"), e.get("name")) for e in ET.parse(out / "dam_break.pvd").getroot().iter("DataSet")}
    assert names == {("0", "fluid"), ("1", "walls")}


def test_vtk_xml_reader_opens_every_frame(small_run):
    """Read the index and its files with VTK's own XML reader, as ParaView does."""
    vtkmodules = pytest.importorskip("vtkmodules.vtkIOXML")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    sim, summary, out = small_run
    entries = vtk.read_pvd(out / "dam_break.pvd")
    n_fluid = int(sim.fluid.sum())
    for t, part, name in entries:
        reader = vtkmodules.vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(out / name))
        reader.Update()
        grid = reader.GetOutput()
        expected = n_fluid if part == 0 else int(sim.wall.sum())
        assert grid.GetNumberOfPoints() == expected
        pd = grid.GetPointData()
        names = {pd.GetArrayName(k) for k in range(pd.GetNumberOfArrays())}
        assert {"velocity", "pressure", "density", "mass", "id", "material"} <= names
        assert vtk_to_numpy(pd.GetArray("velocity")).shape == (expected, 3)
    last = out / [e for e in entries if e[1] == 0][-1][2]
    reader = vtkmodules.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(last))
    reader.Update()
    ids = vtk_to_numpy(reader.GetOutput().GetPointData().GetArray("id"))
    np.testing.assert_array_equal(ids, sim.ids()[sim.fluid])


def test_cli_frames_match_request(tmp_path, capsys, at_output_times):
    code = cli.main(["dam_break", "--dx", "0.1", "--t-end", "0.03", "--frames", "3",
                     "--out", str(tmp_path), "--no-progress"])
    assert code == 0
    entries = vtk.read_pvd(tmp_path / "dam_break.pvd")
    times = [t for t, part, _ in entries if part == 0]
    at_output_times(times, [0.0, 0.01, 0.02, 0.03])
    assert len(list(tmp_path.glob("dam_break_*.vtu"))) == 4
    printed = capsys.readouterr().out
    assert "fluid particle-steps/s" in printed and "dam_break.pvd" in printed


def test_cli_list_and_help(capsys):
    assert cli.main(["list"]) == 0
    out = capsys.readouterr().out
    assert "dam_break" in out and "dam_break_3d" in out
    with pytest.raises(SystemExit) as exit_:
        cli.main(["dam_break", "--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    for option in ("--dx", "--t-end", "--dt", "--integrator", "--kernel", "--precision", "--out", "--frames"):
        assert option in out
    assert "alpha" in out  # the case's own parameters


def test_cli_rejects_bad_input(capsys):
    assert cli.main(["no_such_case"]) == 2
    assert "unknown case" in capsys.readouterr().err
    assert cli.main(["dam_break", "--set", "alpha=abc", "--no-output", "--no-progress"]) == 2
    assert "alpha" in capsys.readouterr().err
    assert cli.main(["dam_break", "--set", "nonsense=1", "--no-output"]) == 2
    assert "no parameter 'nonsense'" in capsys.readouterr().err
