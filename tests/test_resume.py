"""``python -m taisph resume DIR [--t-end T]`` (issue 24): a folder that does not exist
or a run's output folder is refused with exit code 2 and a message saying what to type;
a finished run continues to a later --t-end at its own frame interval; the resumed run
keeps the run's --checkpoint-every and its probes."""

import json

import numpy as np
import pytest

from taisph.cli import main as cli
from taisph.probes.writer import read_csv
from taisph.run import vtk

TINY = ["dam_break", "--dx", "0.1", "--t-end", "0.02", "--frames", "2", "--no-progress"]


def frame_times(out):
    return [t for t, part, _ in vtk.read_pvd(out / "dam_break.pvd") if part == 0]


def run_meta(out):
    return json.loads((out / "checkpoint" / "meta.json").read_text())["run"]


def test_a_missing_folder_is_refused(tmp_path, capsys):
    """Before: "is not a checkpoint folder (no meta.pickle)" for a folder that is not
    there; an empty folder is not a checkpoint folder."""
    folder = tmp_path / "out" / "nosuchdir"
    assert cli.main(["resume", str(folder)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"taisph: error: {folder}: no such"), err
    folder.mkdir(parents=True)
    assert cli.main(["resume", str(folder)]) == 2
    assert capsys.readouterr().err.splitlines() == [f"taisph: error: {folder} is not a checkpoint folder (no meta.json)"]


def test_a_finished_run_is_extended(tmp_path, capsys, at_output_times):
    """A run to 0.02 s in 2 frames, checkpointed every frame: its output folder is
    refused with the hint, resuming it as it is has nothing to do, --t-end before its
    clock is refused, and --t-end 0.04 continues it with 2 more frames at its 0.01 s
    interval, into the same series (frames 3 and 4, the .pvd listing 0 .. 0.04 s),
    checkpointing again."""
    out = tmp_path / "out"
    assert cli.main([*TINY, "--checkpoint-every", "1", "--out", str(out)]) == 0
    capsys.readouterr()
    assert cli.main(["resume", str(out)]) == 2
    assert capsys.readouterr().err.splitlines() == [
        f"taisph: error: {out} is a run's output folder: resume {out / 'checkpoint'}"]
    assert cli.main(["resume", str(out / "checkpoint"), "--no-progress"]) == 0
    assert "nothing left to do" in capsys.readouterr().out
    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.01", "--no-progress"]) == 2
    assert "the run is at t = 0.02 s" in capsys.readouterr().err
    at_output_times(frame_times(out), [0.0, 0.01, 0.02])

    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.04", "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "resuming dam_break at step" in printed and "(to t = 0.04 s, 2 frame(s) left)" in printed
    assert "t = 0.04 s" in [line for line in printed.splitlines() if line.startswith("done:")][-1]  # the summary
    at_output_times(frame_times(out), [0.0, 0.01, 0.02, 0.03, 0.04])
    assert sorted(p.name for p in out.glob("dam_break_*.vtu")) == [f"dam_break_{k:05d}.vtu" for k in range(5)]
    meta = run_meta(out)
    assert meta["t_end"] == pytest.approx(0.04) and meta["frames_left"] == 0


def test_the_run_keeps_its_checkpoint_interval(tmp_path, capsys, at_output_times):
    """--checkpoint-every 2, then resume --t-end 0.05 (3 frames at 0.01 s): the checkpoint
    is written after the resumed run's 2nd frame only, so it has 1 frame left (resume
    forced every frame before: 0 left); resuming that goes on to 0.05 s."""
    out = tmp_path / "out"
    assert cli.main([*TINY, "--checkpoint-every", "2", "--out", str(out)]) == 0
    assert run_meta(out)["checkpoint_every"] == 2
    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.05", "--no-progress"]) == 0
    meta = run_meta(out)
    assert (meta["t_end"], meta["frames_left"], meta["checkpoint_every"]) == (pytest.approx(0.05), 1, 2)
    assert cli.main(["resume", str(out / "checkpoint"), "--no-progress"]) == 0
    assert "(to t = 0.05 s, 1 frame(s) left)" in capsys.readouterr().out
    at_output_times(frame_times(out), [0.0, 0.01, 0.02, 0.03, 0.04, 0.05])


def test_the_run_keeps_its_probes(tmp_path, capsys):
    """A run with a pressure probe, resumed to 0.04 s: probes.csv goes on (one header,
    times increasing past 0.02 s)."""
    out = tmp_path / "out"
    assert cli.main([*TINY, "--checkpoint-every", "1", "--probe", "pressure:P:0.5,0.2", "--out", str(out)]) == 0
    rows = len(read_csv(out / "probes.csv")["time"])
    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.04", "--no-progress"]) == 0
    assert f"appended to {out / 'probes.csv'}" in capsys.readouterr().out
    data = read_csv(out / "probes.csv")
    assert len(data["time"]) > rows and np.all(np.diff(data["time"]) > 0)
    assert data["time"][-1] == pytest.approx(0.04, abs=1e-3)
    assert (out / "probes.csv").read_text().count("time,") == 1


def test_a_run_of_zero_frames_checkpoints_as_finished(tmp_path, capsys):
    """--frames 0 with --checkpoint-every 1: the one output time (t_end) writes a
    checkpoint with no frames left (not -1), which resume reports as finished."""
    out = tmp_path / "out"
    assert cli.main(["hydrostatic_tank", "--dx", "0.1", "--t-end", "0.002", "--frames", "0", "--checkpoint-every", "1",
                "--out", str(out), "--no-progress"]) == 0
    assert json.loads((out / "checkpoint" / "meta.json").read_text())["run"]["frames_left"] == 0
    capsys.readouterr()
    assert cli.main(["resume", str(out / "checkpoint"), "--no-progress"]) == 0
    assert "nothing left to do" in capsys.readouterr().out
