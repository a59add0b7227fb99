"""OUT/run.json (issue 50: an output folder did not say how it was made): every run
command records its command line, versions, the scene's resolved parameters, controls,
machine, start and end, steps, simulated and wall time and how it ended; ``python -m
taisph OUT`` prints it; a resume records the run it continues; ``--version``."""

import datetime
import json
import platform
import re

import taichi

from taisph.cli import main as cli
from taisph.run import record, vtk

RUN = ["dam_break", "--dx", "0.1", "--t-end", "0.1", "--frames", "2", "--no-progress"]


def read(out):
    return json.loads((out / "run.json").read_text())


def test_a_case_run_records_how_it_was_made(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    seen = []
    on_start = vtk.VTKWriter.on_start

    def peek(self, sim):  # the record as the run starts
        seen.append(read(out))
        return on_start(self, sim)

    monkeypatch.setattr(vtk.VTKWriter, "on_start", peek)
    argv = RUN + ["--out", str(out), "--set", "alpha=0.05"]
    assert cli.main(argv) == 0
    assert seen[0]["status"] == "running" and seen[0]["end"] is None
    data = read(out)
    assert data["format"] == "taisph-run" and data["command"] == ["python", "-m", "taisph", *argv]
    assert data["status"] == "done"
    assert data["versions"] == {"taisph": record.versions()["taisph"], "python": platform.python_version(),
                                "taichi": ".".join(map(str, taichi.__version__)),
                                "numpy": __import__("numpy").__version__}
    scene = data["scene"]
    assert scene["name"] == scene["case"] == "dam_break"
    assert scene["arguments"]["dx"] == 0.1 and scene["arguments"]["alpha"] == 0.05
    assert scene["arguments"]["width"] == 1.0 and scene["arguments"]["tank_width"] == 4.0  # the defaults too
    assert scene["parameters"]["alpha"] == 0.05 and "dam_break" in scene["description"]
    assert data["run"] == {"t_end": 0.1, "frames": 2, "checkpoint_every": None, "out": str(out)}
    assert data["controls"]["courant"] == 0.4 and "max_density_error" in data["controls"]
    machine = data["machine"]
    assert machine["cpus"] >= 1 and machine["processor"] and machine["platform"]
    assert (machine["arch"], machine["precision"]) == ("cpu", "f64") and machine["threads"] >= 1
    start, end = (datetime.datetime.fromisoformat(data[k]) for k in ("start", "end"))
    assert start <= end
    assert data["steps"] > 10 and abs(data["sim_time"] - 0.1) < 1e-3 and data["wall_time"] > 0
    assert data["summary"].startswith("200 fluid + ")
    assert not list(out.glob("*.tmp"))

    assert cli.main([str(out)]) == 0  # python -m taisph OUT
    shown = capsys.readouterr().out.split(f"{out}: python -m taisph", 1)[1]
    assert shown.startswith(" dam_break --dx 0.1")
    for words in ("status done started", "the case dam_break: dx=0.1", "alpha=0.05", "steps to t = 0.1",
                  f"Taichi {'.'.join(map(str, taichi.__version__))}", "cpu, f64"):
        assert words in " ".join(shown.split()), words


def test_a_resume_records_the_run_it_continues(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(RUN + ["--out", str(out), "--checkpoint-every", "2"]) == 0
    first = read(out)
    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.2", "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert f"continues the run '{' '.join(first['command'])}' of {first['start']}" in printed
    data = read(out)
    assert data["command"] == ["python", "-m", "taisph", "resume", str(out / "checkpoint"), "--t-end", "0.2",
                               "--no-progress"]
    assert data["status"] == "done" and abs(data["sim_time"] - 0.2) < 1e-3
    assert data["resume_of"] == {"checkpoint": str(out / "checkpoint"), "record": first}
    assert data["scene"]["case"] == "dam_break" and data["scene"]["arguments"]["dx"] == 0.1
    assert cli.main([str(out)]) == 0
    assert "resumes   " + str(out / "checkpoint") in capsys.readouterr().out


def test_a_run_stopped_by_a_guard_says_so(tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(RUN + ["--out", str(out), "--max-density-error", "1e-9"]) == 3
    data = read(out)
    assert data["status"].startswith("stopped by a guard: ") and data["end"]
    assert data["status"].splitlines() == [data["status"]]


def test_a_seed_run_records_its_files(tmp_path, capsys, monkeypatch):
    dat, out = tmp_path / "dat", tmp_path / "out"
    assert cli.main(["export", "dam_break_wedge", "--dat", str(dat), "--set", "dx=0.1"]) == 0
    argv = ["run", str(dat / "particles.dat"), str(dat / "boundary.dat"), "0.01", "2e-4", "pc", "spline",
            "--frames", "1", "--out", str(out), "--no-progress"]
    assert cli.main(argv) == 0
    assert capsys.readouterr().err == ""
    data = read(out)
    assert data["status"] == "done" and data["command"][3:] == argv
    assert data["scene"]["seed_files"] == [str(dat / "particles.dat"), str(dat / "boundary.dat")]

    def interrupt(sim):  # Ctrl-C during the run: one line, exit code 130, the record says so
        raise KeyboardInterrupt

    monkeypatch.setattr(vtk.VTKWriter, "on_frame", lambda self, sim, k: interrupt(sim))
    assert cli.main(argv) == 130
    err = capsys.readouterr().err
    assert err.startswith("taisph run: interrupted at t = ") and len(err.splitlines()) == 1, err
    assert "this command writes no checkpoints: rerun it" in err
    assert read(out)["status"] == "interrupted"


def test_a_folder_without_a_record_and_version(tmp_path, capsys):
    assert cli.main([str(tmp_path)]) == 2
    assert capsys.readouterr().err.splitlines() == [
        f"taisph: error: {tmp_path}: no run.json (a run of taisph writes one into its output folder)"]
    assert cli.main(["--version"]) == 0
    assert re.fullmatch(r"taisph \d+\.\d+\.\d+\S* \(taichi \d+\.\d+\.\d+, Python \d+\.\d+\.\d+\)\n",
                        capsys.readouterr().out)
