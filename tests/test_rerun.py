"""Rerunning into the same output folder (issue 24): the earlier series' own files go,
nothing else does, and the run summary says so. A shorter rerun used to leave the
longer run's last frames (dam_break_00003.vtu ...) beside the new series, unlisted
and unannounced."""

import taisph
from taisph.run import vtk


def frames(folder, name="dam_break"):
    return sorted(p.name for p in folder.glob(f"{name}_*.vtu"))


def run(folder, n_frames):
    sim = taisph.Simulation(taisph.cases.dam_break(dx=0.1))
    try:
        return sim.run(0.01, frames=n_frames, out=folder)
    finally:
        sim.close()


def test_a_shorter_rerun_replaces_the_earlier_series_and_nothing_else(tmp_path):
    run(tmp_path, 5)
    assert frames(tmp_path) == [f"dam_break_{k:05d}.vtu" for k in range(6)]
    foreign = ["notes.txt", "dam_break_last_good.vtu", "other_00001.vtu", "dam_break_0001.vtu",
               "dam_break_3d_00001.vtu", "dam_break.pvd.bak"]
    for name in foreign:
        (tmp_path / name).write_text("not the writer's")
    run(tmp_path, 2)
    assert frames(tmp_path) == ["dam_break_00000.vtu", "dam_break_00001.vtu", "dam_break_00002.vtu",
                                "dam_break_0001.vtu", "dam_break_3d_00001.vtu", "dam_break_last_good.vtu"]
    assert [f for _, part, f in vtk.read_pvd(tmp_path / "dam_break.pvd") if part == 0] == frames(tmp_path)[:3]
    for name in foreign:
        assert (tmp_path / name).read_text() == "not the writer's"
    assert (tmp_path / "walls.vtu").exists()


def test_the_summary_says_how_many_frames_a_rerun_removed(tmp_path):
    first = run(tmp_path, 5)
    assert first.replaced_frames == 0 and "old frames" not in str(first)
    second = run(tmp_path, 2)
    assert second.replaced_frames == 6
    line = str(second)
    assert "6 old frames removed" in line and "\n" not in line


def test_the_walls_file_of_an_earlier_series_goes_with_it(tmp_path):
    """walls.vtu is the series' own when its index lists it: a series without walls
    removes it (and only then)."""
    (tmp_path / "walls.vtu").write_text("unlisted")
    assert vtk.remove_series(tmp_path, "dam_break") == 0
    assert (tmp_path / "walls.vtu").exists()  # no index listing it: not ours
    vtk.write_pvd(tmp_path / "dam_break.pvd", [(0.0, 0, "dam_break_00000.vtu"), (0.0, 1, "walls.vtu")])
    (tmp_path / "dam_break_00000.vtu").write_text("frame")
    assert vtk.remove_series(tmp_path, "dam_break", keep_walls=True) == 1
    assert (tmp_path / "walls.vtu").exists() and not (tmp_path / "dam_break.pvd").exists()
    vtk.write_pvd(tmp_path / "dam_break.pvd", [(0.0, 0, "dam_break_00000.vtu"), (0.0, 1, "walls.vtu")])
    assert vtk.remove_series(tmp_path, "dam_break") == 0
    assert list(tmp_path.iterdir()) == []


def test_a_resumed_series_keeps_its_frames(tmp_path):
    """Resuming from a checkpoint continues the series in the folder: nothing is removed."""
    sim = taisph.Simulation(taisph.cases.dam_break(dx=0.1))
    sim.run(0.01, frames=5, out=tmp_path, checkpoint_every=2)  # the last checkpoint: one frame left
    sim.close()
    resumed = taisph.Simulation.from_checkpoint(tmp_path / "checkpoint")
    meta = resumed.checkpoint_meta
    summary = resumed.run(meta["t_end"], frames=meta["frames_left"], out=meta["out"], _writer_state=meta["writer"])
    resumed.close()
    assert summary.replaced_frames == 0
    assert frames(tmp_path) == [f"dam_break_{k:05d}.vtu" for k in range(6)]
