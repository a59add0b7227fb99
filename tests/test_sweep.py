"""Parameter sweeps on Dask (taisph.sweeps, python -m taisph sweep; docs/sweeps.md).

Real clusters on this machine: a LocalCluster of 2 worker processes, and a `dask
scheduler` with a `dask worker` started as subprocesses on 127.0.0.1. The runs are
tiny (hydrostatic tank, dx = 0.1 m: 50 fluid particles, tens of steps). Every row is
checked against the same combination run directly in this process: the step counts,
the simulated time, the validation error and a guard's diagnosis must be the same.
"""

import csv
import logging
import re
import socket
import subprocess
import sys

import pytest

import taisph
from taisph import validation
from taisph.cli.main import main as cli
from taisph.run.simulation import SimulationError
from taisph.sweeps import SweepError

distributed = pytest.importorskip("distributed", reason="the sweep extra: pip install 'taisph[sweep]'")

CASE = "hydrostatic_tank"


@pytest.fixture(scope="module")
def client():
    """A LocalCluster of 2 worker processes, 1 thread each, shared by the tests below."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=logging.ERROR) as cluster, distributed.Client(cluster) as c:
        yield c


def direct(dt=None, **params):
    """(steps, simulated time, fluid particles) of a direct deterministic run, or the
    first line of its guard's diagnosis."""
    scene = taisph.cases.CASES[CASE](**params)
    if dt is not None:
        scene.dt = dt
    sim = taisph.Simulation(scene, deterministic=True)
    try:
        summary = sim.run()
        return summary.steps, summary.sim_time, summary.fluid_particles
    except SimulationError as err:
        return str(err).splitlines()[0]
    finally:
        sim.close()


def read_csv(folder):
    with open(folder / "sweep.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_local_cluster_runs_every_combination(tmp_path):
    """workers=2: the sweep starts its own LocalCluster; 2 x 2 combinations give 4
    rows with the right parameters, and each row's steps, simulated time and fluid
    particles are those of a direct run of that combination."""
    rows = taisph.sweep(CASE, vary={"dx": [0.1, 0.05], "kernel": ["spline", "wendland"]}, workers=2,
                        out=tmp_path, validate=False, t_end=0.05, deterministic=True, progress=False)
    assert sorted((r["dx"], r["kernel"]) for r in rows) == [(0.05, "spline"), (0.05, "wendland"),
                                                           (0.1, "spline"), (0.1, "wendland")]
    for row in rows:
        assert row["status"] == "ok", row
        assert (row["steps"], row["sim_time_s"], row["fluid_particles"]) == direct(
            dx=row["dx"], kernel=row["kernel"], t_end=0.05), row
        assert row["run"] == f"dx={row['dx']!r}_kernel={row['kernel']}"
        assert row["particle_steps_per_s"] == row["fluid_particles"] * row["steps"] / row["wall_s"]
        assert row["wall_s_per_sim_s"] == row["wall_s"] / row["sim_time_s"]
        assert row["compile_s"] > 0 and row["error"] != row["error"]  # no reference in plain runs: NaN
    written = read_csv(tmp_path)
    assert [r["run"] for r in written] == [r["run"] for r in rows]
    assert [int(r["steps"]) for r in written] == [r["steps"] for r in rows]
    assert all(r["error"] == "nan" for r in written)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sweep.csv", "sweep.json", "sweep.md"]  # no frames
    table = (tmp_path / "sweep.md").read_text().splitlines()
    header = table.index(next(line for line in table if line.startswith("| dx | kernel | status | steps | wall s |")))
    assert len(table) == header + 2 + 4


def test_failed_run_is_a_row_and_the_others_finish(client, tmp_path):
    """A fixed dt 6 times the stability limit (1.6 ms) trips the density guard at step 8
    (0.05 s, 2 steps to the end, trips nothing since no frame shortens a step): its row is
    'failed: ' + the first line of the same diagnosis a direct run gives; the stable
    combination finishes with a direct run's step count. A rerun keeps the failed row
    (no run); with retry_failed it runs that combination again, and only that one."""
    options = dict(client=client, out=tmp_path, validate=False, dx=0.1, t_end=0.1, progress=False)
    rows = taisph.sweep(CASE, vary={"dt": [5e-4, 0.01]}, **options)
    by_dt = {r["dt"]: r for r in rows}
    assert by_dt[5e-4]["status"] == "ok"
    assert by_dt[5e-4]["steps"] == direct(dx=0.1, t_end=0.1, dt=5e-4)[0]
    with pytest.warns(RuntimeWarning, match="above the stability limit"):
        diagnosis = direct(dx=0.1, t_end=0.1, dt=0.01)
    assert diagnosis.startswith("simulation stopped at step")
    assert by_dt[0.01]["status"] == "failed: " + diagnosis
    assert [r["status"] for r in read_csv(tmp_path)] == [r["status"] for r in rows]

    again = taisph.sweep(CASE, vary={"dt": [5e-4, 0.01]}, **options)
    same = lambda rs: [(r["run"], repr(r["wall_s"]), r["worker"], r["status"]) for r in rs]  # noqa: E731 (NaN: repr)
    assert same(again) == same(rows)
    retried = taisph.sweep(CASE, vary={"dt": [5e-4, 0.01]}, retry_failed=True, **options)
    assert [r["run"] for r in retried] == ["dt=0.0005", "dt=0.01"]  # the ok row kept, the failed one run last
    assert retried[0]["wall_s"] == by_dt[5e-4]["wall_s"] and retried[1]["status"] == by_dt[0.01]["status"]
    assert len(read_csv(tmp_path)) == 2


def test_resume_skips_done_rows_and_validation_error_matches(client, tmp_path):
    """Validation runs (the tank has a reference): a row's error and steps equal those
    of taisph.validation.run for the same parameters. A second sweep with one more
    value runs only that one: the first row comes back unchanged (same wall time, same
    worker). A third finds nothing to run and reaches for no cluster at all."""
    options = dict(out=tmp_path, t_end=0.1, samples=4, progress=False)
    first = taisph.sweep(CASE, vary={"dx": [0.1]}, client=client, **options)
    assert len(first) == 1 and first[0]["status"] == "ok"
    outcome = validation.run(CASE, dx=0.1, t_end=0.1, samples=4)
    assert (first[0]["error"], first[0]["steps"], first[0]["sim_time_s"]) == (outcome.error, outcome.steps, 0.1)
    assert first[0]["error_name"] == outcome.error_name

    second = taisph.sweep(CASE, vary={"dx": [0.1, 0.05]}, client=client, **options)
    assert [r["run"] for r in second] == ["dx=0.1", "dx=0.05"]
    for column in ("wall_s", "worker", "error", "steps", "compile_s"):
        assert second[0][column] == first[0][column], column
    assert second[1]["error"] == validation.run(CASE, dx=0.05, t_end=0.1, samples=4).error
    assert [r["run"] for r in read_csv(tmp_path)] == ["dx=0.1", "dx=0.05"]

    # nothing left to run: an unreachable scheduler is never contacted
    third = taisph.sweep(CASE, vary={"dx": [0.1, 0.05]}, scheduler="tcp://127.0.0.1:9", **options)
    assert [(r["run"], r["wall_s"]) for r in third] == [(r["run"], r["wall_s"]) for r in second]

    with pytest.raises(SweepError, match="t_end: was '0.1', now '0.2'"):
        taisph.sweep(CASE, vary={"dx": [0.1]}, client=client, **{**options, "t_end": 0.2})


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def dask_cluster(tmp_path):
    """A real `dask scheduler` and one `dask worker` process (1 thread) on 127.0.0.1."""
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    dask = [sys.executable, "-m", "dask"]
    log = open(tmp_path / "dask.log", "w")
    scheduler = subprocess.Popen([*dask, "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                                 stdout=log, stderr=subprocess.STDOUT)
    worker = subprocess.Popen([*dask, "worker", address, "--host", "127.0.0.1", "--nworkers", "1", "--nthreads", "1",
                               "--no-dashboard", "--local-directory", str(tmp_path / "worker")],
                              stdout=log, stderr=subprocess.STDOUT)
    try:
        yield address
    finally:
        for process in (worker, scheduler):
            process.terminate()
            try:
                process.wait(timeout=20)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        log.close()


def test_cli_sweeps_through_an_existing_scheduler(dask_cluster, tmp_path, capsys):
    """python -m taisph sweep ... --scheduler ADDRESS --frames-per-run: both runs go to
    the user's dask worker (not this process), their rows match direct runs, and each
    run's frames are in DIR/<run name>/."""
    out = tmp_path / "sweep"
    code = cli(["sweep", CASE, "--no-validate", "--vary", "dx=0.1,0.05", "--t-end", "0.05", "--frames", "2",
                "--deterministic", "--scheduler", dask_cluster, "--out", str(out), "--frames-per-run",
                "--no-progress"])
    printed = capsys.readouterr().out
    assert code == 0
    rows = read_csv(out)
    assert [r["dx"] for r in sorted(rows, key=lambda r: -float(r["dx"]))] == ["0.1", "0.05"]
    for row in rows:
        assert row["status"] == "ok"
        assert (int(row["steps"]), float(row["sim_time_s"]), int(row["fluid_particles"])) == direct(
            dx=float(row["dx"]), t_end=0.05, frames=2)
        assert not row["worker"].endswith(f":{__import__('os').getpid()}")
        frames = sorted(p.name for p in (out / row["run"]).iterdir())
        assert frames == ["hydrostatic_tank.pvd", "hydrostatic_tank_00000.vtu", "hydrostatic_tank_00001.vtu",
                          "hydrostatic_tank_00002.vtu", "walls.vtu"], frames
    assert "2 runs: 2 ok, 0 failed" in printed and "| dx | status | steps |" in printed


SCENE_FILE = """\
name = "pool"
dim = 2
dx = 0.1
t_end = 0.05
frames = 1
solver = "wcsph"

[[fluid]]
box = [[0.0, 0.0], [1.0, 0.5]]

[[walls]]
name = "tank"
box = [[0.0, 0.0], [1.0, 1.0]]
"""


def test_cli_sweeps_a_scene_file(tmp_path, capsys):
    """python -m taisph sweep SCENE.toml --vary dx=0.1,0.05 --set alpha=0.05 (issue 16:
    CASE_OR_SCENE): plain runs of the file (it has no reference), on a LocalCluster of
    one worker; each row's steps, simulated time and fluid particles are those of the
    scene file run directly with that dx and alpha; the table names the file."""
    path = tmp_path / "pool.toml"
    path.write_text(SCENE_FILE)
    out = tmp_path / "sweep"
    code = cli(["sweep", str(path), "--vary", "dx=0.1,0.05", "--set", "alpha=0.05", "--deterministic",
                "--workers", "1", "--out", str(out), "--no-progress"])
    printed = capsys.readouterr().out
    assert code == 0, printed
    from taisph.formats.scenefile import load

    for row in read_csv(out):
        assert row["status"] == "ok" and row["error"] == "nan"
        scene = load(path, {"dx": float(row["dx"]), "physics.alpha": 0.05})[0]
        assert scene.terms_by_name["artificial_viscosity"].values["alpha"] == 0.05
        sim = taisph.Simulation(scene, deterministic=True)
        summary = sim.run()
        sim.close()
        assert (int(row["steps"]), float(row["sim_time_s"]), int(row["fluid_particles"])) == (
            summary.steps, summary.sim_time, summary.fluid_particles)
    assert sorted(r["dx"] for r in read_csv(out)) == ["0.05", "0.1"]
    assert f"# Sweep of {path}" in printed and "2 runs: 2 ok, 0 failed" in printed


@pytest.mark.parametrize("argv, message", [
    (["nocase", "--vary", "dx=0.1"], "unknown case 'nocase'; cases: channel, couette, cylinder, dam_break"),
    ([CASE, "--vary", "dxx=0.1"], "hydrostatic_tank has no parameter 'dxx'; allowed are case parameters: dx,"),
    ([CASE, "--vary", "dx=0.1,abc"], "dx: cannot read 'abc'"),
    ([CASE, "--vary", "precision=f16"], "precision: cannot read 'f16'"),
    ([CASE, "--vary", "dx=0.1,-0.05"], "hydrostatic_tank: dx must be > 0, got -0.05"),  # the case's declared range
    ([CASE, "--vary", "samples=0"], "hydrostatic_tank: samples must be an integer >= 1, got 0"),
    ([CASE, "--vary", "dx=0.1", "--set", "alpha=abc"], "--set alpha=abc: alpha must be in [0, 2]"),  # as CASE --set
    ([CASE, "--vary", "dx=0.1", "--set", "alpha=-1"], "hydrostatic_tank: alpha must be in [0, 2], got -1.0"),
    ([CASE, "--vary", "dx=0.1", "--bogus"], "unrecognized arguments: --bogus"),
    ([CASE, "--vary", "dt=1e-4,1e-3"], "dt: not available when each run is hydrostatic_tank's validation"),
    (["dam_break", "--vary", "dx=0.1", "--t-end", "0.1"], "t_end: dam_break's validation runs to T_end"),
    ([CASE, "--vary", "dx=0.1,0.1"], "dx: a value is given twice"),
    (["nothere.toml", "--vary", "dx=0.1"], "nothere.toml: no such scene file"),
    (["dam_break_probes_2d.toml", "--vary", "dxx=0.1"], "cases/dam_break_probes_2d.toml has no parameter 'dxx'; "
                                                        "allowed are case parameters: dx, t_end, frames, "
                                                        "integrator, kernel, h_factor, alpha, delta, xsph, shifting, density_relaxation;"),
    (["dam_break_probes_2d.toml", "--vary", "dx=0.1,-1"], "cases/dam_break_probes_2d.toml: dx must be in (0, 1000], got -1.0"),
])
def test_bad_input_is_refused_before_any_run(tmp_path, capsys, argv, message):
    """Exit code 2 and a message naming the problem and what is allowed; no folder is
    made, no cluster started."""
    out = tmp_path / "sweep"
    assert cli(["sweep", *argv, "--out", str(out)]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_import_taisph_does_not_import_dask():
    """taisph.sweep is loaded on first use: `import taisph` stays free of Dask."""
    code = ("import sys, taisph; assert 'distributed' not in sys.modules and 'dask' not in sys.modules; "
            "assert taisph.sweep.__module__ == 'taisph.sweeps'")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, timeout=120)


def test_a_scene_file_factory_declares_its_signature_and_ranges():
    """scene_factory: a signature with the file's values as defaults and the ranges
    the file's checker uses, checked on every call as a case's are."""
    import inspect

    from taisph.formats.scenefile import SWEEP_KEYS, scene_factory
    from taisph.formats.scenefile_spec import RANGES, read
    from taisph.scene.catalogue import cases_folder
    from taisph.scene.parameters import ParameterError

    factory = scene_factory("dam_break_probes_2d.toml")
    spec = read(cases_folder() / "dam_break_probes_2d.toml")
    assert {k: p.default for k, p in inspect.signature(factory).parameters.items()} == {
        k: getattr(spec, k) for k in SWEEP_KEYS}
    assert factory.ranges == {k: RANGES[key] for k, key in SWEEP_KEYS.items()}
    assert (factory.__name__, factory.courant) == ("dam_break_probes_2d", 0.125)
    with pytest.raises(ParameterError, match=re.escape("dam_break_probes_2d: delta must be in [0, 1], got 1e+300")):
        factory(delta=1e300)
    scene = factory(0.1, alpha=0.05)
    assert scene.dx == 0.1 and scene.terms_by_name["artificial_viscosity"].values["alpha"] == 0.05


def test_a_sweep_varies_the_dfsph_controls_and_takes_a_scene_files_own(tmp_path):
    """The controls a run can set (timestep.SETTABLE: dt_max, DFSPH's tolerances and
    iteration limits) are sweep settings too, and a scene file's own values reach its
    runs unless the sweep sets them."""
    from taisph.sweeps.plan import plan_tasks

    tasks, _ = plan_tasks("hydrostatic_tank", {"dfsph_max_iterations": ["50", "100"]}, {"dt_max": "0.001"},
                          validate=False)
    assert [(t.settings["dfsph_max_iterations"], t.settings["dt_max"]) for t in tasks] == [(50, 0.001), (100, 0.001)]
    path = tmp_path / "tank.toml"
    path.write_text(SCENE_FILE.replace('solver = "wcsph"', 'solver = "wcsph"\ndfsph_tolerance = 0.001'))
    tasks, _ = plan_tasks(str(path), {"dx": ["0.05"]}, {}, validate=False)
    assert tasks[0].settings["dfsph_tolerance"] == 0.001
