"""Progress where standard error is not a terminal (issue 50: a batch job, ``2> log``, a
cluster's queue saw nothing until the run ended): a plain line every N seconds with the
simulated time of the end time, steps, steps/s and the time left; ``--no-progress``
turns it off in every run command. A run in a subprocess whose standard error is a pipe:
tests/test_interrupt.py::test_sigint_to_a_running_command (its progress lines, then the
line Ctrl-C ends it with)."""

import io
import re
import time

import pytest

from taisph.cli import main as cli
from taisph.run import progress
from taisph.run.progress import EVERY_VARIABLE, Progress

LINE = re.compile(r"simulating: t = [\d.e+-]+ / 0\.5 s \([\d.]+ %\), \d+ steps, \d+ steps/s, \d+:\d\d elapsed, "
                  r"(about \d+:\d\d(:\d\d)? left|time left unknown yet)")


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_plain_lines_every_interval_on_a_stream_that_is_not_a_terminal():
    stream = io.StringIO()
    with Progress(0.0, 0.5, every=0.05, stream=stream) as bar:
        assert bar.plain
        for k in range(1, 11):
            time.sleep(0.02)
            bar.update(0.05 * k, 10 * k)
    lines = stream.getvalue().splitlines()
    assert 2 <= len(lines) <= 5, lines  # 0.2 s of updates, a line every 0.05 s at most
    assert all(LINE.fullmatch(line) for line in lines), lines
    with Progress(0.0, 0.5, enabled=False, stream=stream) as bar:
        bar.update(0.5, 10)
    assert len(stream.getvalue().splitlines()) == len(lines)


def test_a_terminal_gets_the_bar_and_the_environment_sets_the_interval(monkeypatch):
    stream = Terminal()
    with Progress(0.0, 1.0, stream=stream) as bar:
        assert not bar.plain
        bar.update(0.5, 10, force=True)
    assert "steps/s" in stream.getvalue()
    monkeypatch.setenv(EVERY_VARIABLE, "0.25")
    assert progress.line_interval() == 0.25
    monkeypatch.setenv(EVERY_VARIABLE, "soon")
    with pytest.warns(UserWarning, match=f"{EVERY_VARIABLE}='soon' is not a number of seconds > 0"):
        assert progress.line_interval() == progress.EVERY
    assert progress.clock(3725) == "1:02:05" and progress.clock(65) == "1:05"


def quiet(capsys, monkeypatch, argv):
    """`argv` run with a progress line due every millisecond: nothing on stderr."""
    monkeypatch.setenv(EVERY_VARIABLE, "0.001")
    assert cli.main(argv) == 0
    assert capsys.readouterr().err == ""


def test_no_progress_silences_every_run_command(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    monkeypatch.setenv(EVERY_VARIABLE, "0.001")
    assert cli.main(["dam_break", "--dx", "0.1", "--t-end", "0.1", "--frames", "2", "--out", str(out),
                     "--checkpoint-every", "2"]) == 0
    assert "simulating: t = " in capsys.readouterr().err  # without --no-progress: lines
    quiet(capsys, monkeypatch, ["dam_break", "--dx", "0.1", "--t-end", "0.1", "--frames", "2", "--out", str(out),
                                "--checkpoint-every", "2", "--no-progress"])
    quiet(capsys, monkeypatch, ["resume", str(out / "checkpoint"), "--t-end", "0.2", "--no-progress"])
    # a scene file's run: tests/test_interrupt.py (one line on stderr with --no-progress); the seed's run:
    # tests/test_run_record.py
