"""Ctrl-C (issue 50): a run, a scene-file run or a resume stopped by a KeyboardInterrupt
ends with one line on stderr (no traceback) naming the last checkpoint and the command
that resumes it, or saying that none was written and how to have one; exit code 130;
the output folder stays openable: its .pvd parses and lists only files on disk, no
temporary file is left, and OUT/run.json says "interrupted"."""

import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from taisph.cli import main as cli
from taisph.run import vtk

PROGRESS = re.compile(r"simulating: t = [\d.e+-]+ / 100 s \([\d.]+ %\), \d+ steps, \d+ steps/s, \d+:\d\d elapsed, "
                      r"(about [\d:]+ left|time left unknown yet)")
RUN = ["dam_break", "--dx", "0.1", "--t-end", "0.4", "--frames", "8", "--no-progress"]


def interrupt_at_pvd(monkeypatch, count: int):
    """Ctrl-C while the `count`-th index is being written, after the frame's .vtu files:
    its temporary file is written, not yet renamed, when the KeyboardInterrupt arrives."""
    calls = []
    replace = os.replace

    def interrupted_replace(src, dst):
        if str(src).endswith(".pvd.tmp"):
            calls.append(dst)
            if len(calls) == count:
                raise KeyboardInterrupt
        return replace(src, dst)

    monkeypatch.setattr(vtk.os, "replace", interrupted_replace)


def assert_openable(out, name="dam_break"):
    entries = vtk.read_pvd(out / f"{name}.pvd")
    assert entries, "the index lists the frames written before the interruption"
    assert all((out / file).is_file() for _, _, file in entries)
    assert not list(out.glob("*.tmp")) and not list(out.glob("**/*.tmp"))
    record = json.loads((out / "run.json").read_text())
    assert record["status"] == "interrupted" and record["end"] and record["steps"] > 0
    return entries, record


def test_ctrl_c_names_the_last_checkpoint_and_the_resume_command(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    interrupt_at_pvd(monkeypatch, 5)  # frames 0-3 listed; checkpoints after frames 1 and 2 (every 1)
    assert cli.main(RUN + ["--out", str(out), "--checkpoint-every", "1"]) == 130
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1, err
    line = err.strip()
    assert line.startswith("taisph: interrupted at t = ")
    entries, record = assert_openable(out)
    times = [t for t, part, _ in entries if part == 0]
    assert times == pytest.approx([0, 0.05, 0.1, 0.15], abs=0.005)  # the frames before the interruption
    assert f"last checkpoint {out / 'checkpoint'} (t = {times[-1]:.6g} s)" in line  # written with the last one
    assert line.endswith(f"continue with: python -m taisph resume {out / 'checkpoint'}")


def test_ctrl_c_without_checkpoints_says_how_to_have_one(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    interrupt_at_pvd(monkeypatch, 3)
    assert cli.main(RUN + ["--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1, err
    assert "no checkpoint was written (rerun with --checkpoint-every N" in err
    assert "resume OUT/checkpoint" in err and "Traceback" not in err
    assert_openable(out)


def test_an_earlier_runs_checkpoint_is_not_offered(tmp_path, capsys, monkeypatch):
    """OUT/checkpoint of an earlier run in the same folder would resume that run, not this one."""
    out = tmp_path / "out"
    assert cli.main(RUN + ["--out", str(out), "--checkpoint-every", "4"]) == 0
    interrupt_at_pvd(monkeypatch, 3)
    assert cli.main(RUN + ["--out", str(out)]) == 130
    assert "no checkpoint was written" in capsys.readouterr().err


def test_ctrl_c_in_a_resume(tmp_path, capsys, monkeypatch):
    """The checkpoint a run resumed from resumes it again (until it writes a later one)."""
    out = tmp_path / "out"
    assert cli.main(RUN[:4] + ["0.1", "--frames", "2", "--no-progress", "--out", str(out), "--checkpoint-every",
                               "2", "--probe", "pressure:P:1.5,0.1"]) == 0  # a finished run, checkpointed at its end
    capsys.readouterr()
    interrupt_at_pvd(monkeypatch, 2)  # the resumed run's second frame
    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.3", "--no-progress"]) == 130
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1, err
    assert err.strip().endswith(f"continue with: python -m taisph resume {out / 'checkpoint'}")
    _, record = assert_openable(out)
    assert record["resume_of"]["record"]["command"][3:5] == ["dam_break", "--dx"]


def test_ctrl_c_in_a_scene_file_run(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    interrupt_at_pvd(monkeypatch, 2)
    assert cli.main(["dam_break_probes_2d.toml", "--dx", "0.05", "--t-end", "0.02", "--frames", "4", "--no-progress",
                     "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "no checkpoint was written" in err, err
    assert_openable(out, "dam_break_probes_2d")


def test_ctrl_c_before_the_run_began(tmp_path, capsys, monkeypatch):
    from taisph.cli import case

    def compiling(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(case, "build_simulation", compiling)
    assert cli.main(RUN + ["--out", str(tmp_path / "out")]) == 130
    assert capsys.readouterr().err.splitlines() == [
        "taisph: interrupted before the run began (while building or compiling); no checkpoint to resume"]


def test_sigint_to_a_running_command(tmp_path):
    """As a user meets it, in a batch job: SIGINT (Ctrl-C) to ``python -m taisph`` with
    standard error to a pipe, once it has written a checkpoint: plain progress lines
    (tests/test_progress_plain.py), then one line naming the checkpoint; exit code 130;
    an index of whole frames."""
    out = tmp_path / "out"
    env = {**os.environ, "PYTHONWARNINGS": "ignore", "TAISPH_PROGRESS_EVERY": "0.05"}
    argv = [sys.executable, "-m", "taisph", "dam_break", "--dx", "0.1", "--t-end", "100", "--frames", "4000",
            "--checkpoint-every", "2", "--out", str(out)]
    run = subprocess.Popen(argv, cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not (out / "checkpoint" / "meta.json").exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        time.sleep(0.5)
        run.send_signal(signal.SIGINT)
        printed, err = run.communicate(timeout=120)
    finally:
        if run.poll() is None:
            run.kill()
    assert run.returncode == 130, err
    *progress, last = err.splitlines()
    assert progress and all(PROGRESS.fullmatch(line) for line in progress), err
    assert last.startswith("taisph: interrupted at t = ") and "last checkpoint" in last
    assert last.endswith(f"python -m taisph resume {out / 'checkpoint'}")
    assert "simulating" not in printed  # standard output: results only
    assert_openable(out)


def test_ctrl_c_in_a_run_that_writes_nothing(tmp_path, capsys, monkeypatch):
    from taisph.run import progress

    def update(self, t, steps, force=False):
        raise KeyboardInterrupt

    monkeypatch.setattr(progress.Progress, "update", update)
    monkeypatch.chdir(tmp_path)
    assert cli.main(RUN + ["--no-output"]) == 130
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("taisph: interrupted at t = "), err
    assert err.strip().endswith("the run wrote nothing (--no-output), nothing to resume")
    assert list(tmp_path.iterdir()) == []
