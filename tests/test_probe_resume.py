"""A resumed run continues its probes exactly once (issue 50): a run checkpointed every 2
frames and stopped (Ctrl-C) after the next frame has written probe rows past its last
checkpoint; resuming from that checkpoint with ``Probes(..., append=True,
resume_time=sim.time)`` (what ``python -m taisph resume`` does) first drops those rows,
so probes.csv runs forward in time, each time once, and holds exactly the rows of the run
that was never stopped (deterministic runs: bit for bit, so the CSV text is equal). Before,
the rows after the checkpoint were written twice, the file running backwards."""

import shutil

import numpy as np
import pytest

import taisph
from taisph.cli import main as cli
from taisph.probes import Probes, elevation, pressure, read_csv
from taisph.probes.writer import continue_csv

T_END, FRAMES = 0.02, 4  # a checkpoint after frames 2 and 4 (every 2); Ctrl-C after frame 3


def probes(integrator):
    """Every step, and (pc) every 2 steps: a checkpoint's step count is odd or even alike."""
    return [pressure("P", (0.3, 0.1))] + ([elevation("H", 0.5, every=2)] if integrator == "pc" else [])


def run(out, integrator, stop_at=None):
    """A dam break (dx = 0.1) to T_END in FRAMES frames, checkpointed every 2, its probes to
    OUT/probes.csv; with `stop_at` a KeyboardInterrupt after that frame (0-based), as Ctrl-C."""
    sim = taisph.Simulation(taisph.cases.dam_break(dx=0.1, integrator=integrator), deterministic=True)
    writer = Probes(probes(integrator), path=out / "probes.csv")
    frame = iter(range(FRAMES))

    def stop(_):
        if next(frame) == stop_at:
            raise KeyboardInterrupt

    try:
        sim.run(T_END, frames=FRAMES, out=out, checkpoint_every=2, callback=stop, writers=[writer])
    except KeyboardInterrupt:
        pass
    finally:
        writer.close()
        sim.close()


def resume(folder):
    """Continue the checkpoint `folder` as ``python -m taisph resume`` does."""
    sim = taisph.Simulation.from_checkpoint(folder)
    meta = sim.checkpoint_meta
    writer = Probes(meta["probes"], walls=meta["wall_groups"], path=folder.parent / "probes.csv", append=True,
                    resume_time=sim.time)
    try:
        sim.run(meta["t_end"], frames=meta["frames_left"], out=meta["out"], checkpoint_every=meta["checkpoint_every"],
                writers=[writer], _writer_state=meta["writer"])
    finally:
        writer.close()
        sim.close()
    return meta


@pytest.mark.parametrize("integrator", ["pc", "euler"])
def test_a_resumed_run_writes_each_row_once(tmp_path, integrator):
    """pc: rows labelled with the state after their step (the checkpoint's own row is
    kept); euler: with the step's start (the row at the checkpoint's time comes again
    from the resumed run and is written once)."""
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    run(whole, integrator)
    run(stopped, integrator, stop_at=2)
    before = read_csv(stopped / "probes.csv")["time"]
    checkpoint_time = taisph.Simulation.from_checkpoint(stopped / "checkpoint").time
    assert before[-1] > checkpoint_time  # rows past the checkpoint: what used to come twice
    meta = resume(stopped / "checkpoint")
    assert meta["frames_left"] == 2
    times = read_csv(stopped / "probes.csv")["time"]
    assert np.all(np.diff(times) > 0) and len(set(times)) == len(times)
    assert (stopped / "probes.csv").read_text() == (whole / "probes.csv").read_text()


def test_the_resume_command_drops_the_rows_after_its_checkpoint(tmp_path, capsys):
    """The command line: a run to 0.01 s checkpointed there, resumed to 0.02 s; then the
    checkpoint at 0.01 s put back (a run stopped after writing rows past it) and resumed
    again: probes.csv is the same text, each row once."""
    out = tmp_path / "out"
    assert cli.main(["dam_break", "--dx", "0.1", "--t-end", "0.01", "--frames", "1", "--no-progress", "--deterministic",
                     "--checkpoint-every", "1", "--probe", "pressure:P:0.3,0.1", "--out", str(out)]) == 0
    shutil.copytree(out / "checkpoint", tmp_path / "saved")
    resume = ["resume", str(out / "checkpoint"), "--t-end", "0.02", "--no-progress"]
    assert cli.main(resume) == 0
    whole = (out / "probes.csv").read_text()
    shutil.rmtree(out / "checkpoint")
    shutil.copytree(tmp_path / "saved", out / "checkpoint")
    assert cli.main(resume) == 0
    assert (out / "probes.csv").read_text() == whole
    times = read_csv(out / "probes.csv")["time"]
    assert np.all(np.diff(times) > 0) and times[-1] == pytest.approx(0.02, abs=1e-3)


def test_continue_csv_drops_later_rows_and_a_cut_line_atomically(tmp_path):
    """The rewrite on its own: the header kept, rows after the time dropped (at it: kept,
    or dropped when not inclusive), a last line cut short by a kill dropped, times compared
    exactly (repr); a CSV of other probes refused, the file untouched."""
    path = tmp_path / "probes.csv"
    text = "time,P\n0.0,1\n0.1,2\n0.30000000000000004,3\n0.4,4\n0.5,5\n0.6,"
    path.write_text(text)
    continue_csv(path, "time,P", 0.30000000000000004)
    assert path.read_text() == "time,P\n0.0,1\n0.1,2\n0.30000000000000004,3\n"
    continue_csv(path, "time,P", 0.30000000000000004, inclusive=False)
    assert path.read_text() == "time,P\n0.0,1\n0.1,2\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["probes.csv"]  # no temporary file left
    with pytest.raises(ValueError, match=r"probes.csv: its columns \(time,P\) are not the resumed run's probes' "
                                         r"\(time,Q\)"):
        continue_csv(path, "time,Q", 0.0)
    assert path.read_text() == "time,P\n0.0,1\n0.1,2\n"


def test_resume_time_must_be_a_time():
    with pytest.raises(ValueError, match=r"resume_time = 'soon': expected a finite time"):
        Probes([pressure("P", (0.3, 0.1))], append=True, resume_time="soon")
