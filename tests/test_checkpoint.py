"""Checkpoints in a plain, versioned schema (meta.json, scene.npz, state.npz; no pickle):
a scene round-trips through plain data exactly, a run's target and what the command
line needs to resume it are recorded, and a folder of another version, a run folder, or
no folder at all is refused with one line saying what to do."""

import json
import pickle
import shutil

import numpy as np
import pytest
import taichi as ti

import taisph
from taisph.probes import Probe, Probes, elevation, force, pressure
from taisph.run import checkpoint, vtk
from taisph.run.checkpoint import SCHEMA, CheckpointError, CheckpointWriter
from taisph.scene.serialize import TERMS, SceneDataError, plain, scene_from_data, scene_to_data
from taisph.terms import Term

STEPS = 5
SMALLER = {"dam_break_3d": {"dx": 0.1}}  # the simulated comparison at fewer particles (60 868 at its default)


def round_trip(scene):
    """The scene rebuilt from its plain data, through strict JSON and an npz file's dtypes."""
    data, arrays = scene_to_data(scene)
    text = json.dumps(data, allow_nan=False)
    assert json.loads(text) == data
    return scene_from_data(json.loads(text), {k: np.array(v) for k, v in arrays.items()})


def assert_same_scene(a, b):
    assert b.describe() == a.describe()
    for name in ("position", "velocity", "mass", "density", "kind", "material"):
        x, y = getattr(a, name), getattr(b, name)
        assert y.dtype == x.dtype
        np.testing.assert_array_equal(y, x)
    assert sorted(b.quantities) == sorted(a.quantities)
    for name in a.quantities:
        np.testing.assert_array_equal(b.quantities[name], a.quantities[name])
    for s, t in zip(a.terms, b.terms, strict=True):
        assert type(t) is type(s) and t.compile_key() == s.compile_key() and plain(t.values) == plain(s.values)
    assert b.materials == a.materials and type(b.eos) is type(a.eos) and b.eos.compile_key() == a.eos.compile_key()
    for key in ("dt", "t_end", "frames", "courant", "solver", "neighbour_skin", "remove_escaped", "open_faces",
                "periodic", "kernel", "integrator", "dx", "smoothing_length", "name", "dim"):
        assert getattr(b, key) == getattr(a, key), key
    for lo_hi_a, lo_hi_b in zip(a.domain, b.domain):
        np.testing.assert_array_equal(lo_hi_b, lo_hi_a)


@pytest.mark.parametrize("name", list(taisph.cases.CASES))
def test_every_case_round_trips_through_plain_data(name):
    """Defaults of every built-in case: the rebuilt scene describes itself the same, before
    and after validation (Gravity fills its default vector in then), with equal arrays,
    terms (class, compile key, parameters), materials, equation of state and settings."""
    scene = taisph.cases.CASES[name]()
    rebuilt = round_trip(scene)
    assert_same_scene(scene, rebuilt)
    scene.validate()
    rebuilt.validate()
    assert_same_scene(scene, rebuilt)
    assert round_trip(rebuilt).describe() == scene.describe()


@pytest.mark.parametrize("name", list(taisph.cases.CASES))
def test_a_rebuilt_case_simulates_as_the_original(name):
    """Deterministic mode: 5 steps of the rebuilt scene give the original's state bit for bit."""
    scene = taisph.cases.CASES[name](**SMALLER.get(name, {}))
    rebuilt = round_trip(scene)
    a = taisph.Simulation(scene, deterministic=True)
    b = taisph.Simulation(rebuilt, deterministic=True)
    a.step(STEPS)
    b.step(STEPS)
    assert b.steps == a.steps and b.time == a.time
    for rows_a, rows_b in zip(a.state.to_numpy(), b.state.to_numpy(), strict=True):
        np.testing.assert_array_equal(rows_b, rows_a)
    a.close()
    b.close()


@ti.data_oriented
class Drag(Term):
    """A user's own term (not in taisph.terms): dv/dt -= k v."""

    name = "drag"
    params = {"k": 1.0}

    @ti.func
    def particle(self, s: ti.template(), i, rates: ti.template()):
        rates.acc -= s.params[self.p.k] * s.Sv[self.q.velocity, i]


def test_dfsph_a_users_term_and_extra_quantities_round_trip():
    """DFSPH, a term class outside taisph (rebuilt from its module), Gravity given
    explicitly, a per-particle quantity and a non-finite control-like value survive."""
    scene = taisph.cases.dam_break(dx=0.1)
    scene.solver = "dfsph"
    scene.terms.append(Drag(k=0.5))
    scene.terms_by_name["gravity"].values["gravity"] = np.array([0.0, -5.0])
    scene.quantities["tracer"] = np.arange(scene.n, dtype=float)
    data, _ = scene_to_data(scene)
    assert data["terms"][-1] == {"name": "drag", "class": "Drag", "params": {"k": 0.5}, "options": {},
                                 "module": Drag.__module__}
    assert all("module" not in t for t in data["terms"][:-1])
    rebuilt = round_trip(scene)
    assert_same_scene(scene, rebuilt)
    assert rebuilt.terms_by_name["gravity"].values["gravity"] == (0.0, -5.0)


def test_the_registry_has_every_built_in_term_and_equation_of_state():
    import taisph.terms
    from taisph.scene.serialize import EOS

    built_in = {n for n in taisph.terms.__all__ if isinstance(getattr(taisph.terms, n), type)
                and issubclass(getattr(taisph.terms, n), taisph.terms.Term) and n != "Term"}
    assert set(TERMS) == built_in and all(TERMS[n] is getattr(taisph.terms, n) for n in built_in)
    assert set(EOS) == set(taisph.eos.__all__) - {"tait", "ideal_gas"}


def test_unknown_term_class_is_refused_by_name():
    data, arrays = scene_to_data(taisph.cases.hydrostatic_tank())
    data["terms"][0]["class"] = "Vorticity"
    with pytest.raises(SceneDataError, match="term 'continuity' of class 'Vorticity': this taisph has no such class"):
        scene_from_data(data, arrays)


# --- the checkpoint folder ------------------------------------------------------------
@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A checkpoint written by a run with ParaView frames, checkpoint_every and probes."""
    out = tmp_path_factory.mktemp("run")
    sim = taisph.Simulation(taisph.cases.dam_break(dx=0.1), deterministic=True)
    walls = np.flatnonzero(sim.wall)
    probes = [pressure("P1", (3.9, 0.2)), pressure("face", (3.9, 0.1), to=(3.9, 0.3), every=2),
              elevation("H", 2.0), force("floor", "walls"), force("ids", walls[:5]), force("mask", sim.wall),
              force("slice", slice(0, 3)), Probe("range", "force", walls=range(2, 4))]
    writer = CheckpointWriter(out / "mine", 2, 0.02, 2, probes=probes, wall_groups={"walls": walls})
    sim.run(0.02, frames=2, out=out, checkpoint_every=1, writers=[writer])
    return sim, out, probes, walls


def test_a_checkpoint_is_plain_json_and_npz(saved):
    sim, out, _, _ = saved
    folder = out / "checkpoint"
    assert sorted(p.name for p in folder.iterdir()) == ["meta.json", "scene.npz", "state.npz"]
    meta = json.loads((folder / "meta.json").read_text())
    assert sorted(meta) == ["controls", "format", "grid", "run", "runtime", "scene", "schema", "serial_sort", "taisph"]
    assert (meta["format"], meta["schema"], meta["taisph"]) == ("taisph-checkpoint", SCHEMA, checkpoint.taisph_version())
    assert sorted(meta["run"]) == ["checkpoint_every", "frames_left", "out", "output_times", "probes", "t_end",
                                   "wall_groups", "writer"]
    assert meta["controls"]["dt_max"] == {"float": "inf"} and meta["controls"]["deterministic"] is True
    assert [t["name"] for t in meta["scene"]["terms"]] == [t.name for t in sim.scene.terms]
    for name in ("scene.npz", "state.npz"):
        with np.load(folder / name, allow_pickle=False) as data:
            assert all(data[k].dtype != object for k in data)


def test_checkpoint_meta_has_the_runs_target_and_what_the_command_line_needs(saved, at_output_times):
    sim, out, probes, walls = saved
    resumed = taisph.Simulation.from_checkpoint(out / "checkpoint")
    meta = resumed.checkpoint_meta
    assert meta["t_end"] == 0.02 and meta["frames_left"] == 0 and meta["out"] == str(out)
    assert meta["checkpoint_every"] == 1 and meta["probes"] is None and meta["wall_groups"] is None
    frame, entries = meta["writer"]
    assert frame == 3 and entries == [tuple(e) for e in vtk.read_pvd(out / "dam_break.pvd")]
    at_output_times([e[0] for e in entries if e[1] == 0], [0.0, 0.01, 0.02])
    assert all(type(e) is tuple for e in entries)
    resumed.close()
    mine = taisph.Simulation.from_checkpoint(out / "mine").checkpoint_meta
    assert mine["checkpoint_every"] == 2 and mine["writer"] is None and mine["frames_left"] == 0
    for p, q in zip(probes, mine["probes"], strict=True):
        assert (q.name, q.kind, q.at, q.to, q.every) == (p.name, p.kind, p.at, p.to, p.every)
        assert type(q.walls) is type(p.walls)
        if isinstance(p.walls, np.ndarray):
            assert q.walls.dtype.kind == p.walls.dtype.kind and np.array_equal(q.walls, p.walls)
        else:
            assert q.walls == p.walls
    assert list(mine["wall_groups"]) == ["walls"]
    np.testing.assert_array_equal(mine["wall_groups"]["walls"], walls)
    assert mine["controls"] == {f: getattr(sim.controls, f) for f in mine["controls"]}
    assert mine["runtime"] == (sim.runtime.arch, sim.runtime.precision) and mine["serial_sort"] is True
    np.testing.assert_array_equal(mine["grid"].lo, sim.state.grid.lo)
    assert mine["grid"].shape == sim.state.grid.shape


def test_probes_of_a_runs_writers_are_recorded(tmp_path):
    """``probes_of(writers)`` finds the Probes writers of a run and their wall groups
    (what :meth:`taisph.Simulation.run` gives its checkpoint writer)."""
    sim = taisph.Simulation(taisph.cases.hydrostatic_tank(dx=0.05))
    groups = {"floor": np.flatnonzero(sim.wall & (sim.positions()[:, 1] < 0))}
    probes = Probes([pressure("p", (0.5, 0.1)), force("f", "floor", every=2)], walls=groups)
    assert checkpoint.probes_of([object(), probes]) == (probes.probes, probes.walls)
    assert checkpoint.probes_of([]) == (None, None)
    writer = CheckpointWriter(tmp_path / "cp", 1, 0.01, 1, None, *checkpoint.probes_of([probes]))
    sim.run(0.01, frames=1, writers=[probes, writer])
    meta = taisph.Simulation.from_checkpoint(tmp_path / "cp").checkpoint_meta
    assert meta["probes"] == probes.probes and meta["checkpoint_every"] == 1
    np.testing.assert_array_equal(meta["wall_groups"]["floor"], groups["floor"])


def test_a_resumed_run_continues_bit_for_bit_with_a_changed_scene(tmp_path):
    """Parameters, a material and a control changed before the checkpoint are the
    resumed run's too (they live in the scene and the controls the checkpoint holds)."""
    a = taisph.Simulation(taisph.cases.dam_break(dx=0.1), deterministic=True)
    a.set(alpha=0.05, gravity=(0.5, -9.0), courant=0.3)
    a.set_material(0, c0=40.0)
    a.step(3)
    a.save_checkpoint(tmp_path / "cp")
    b = taisph.Simulation.from_checkpoint(tmp_path / "cp")
    assert b.parameters()["alpha"] == 0.05 and b.controls.courant == 0.3 and b.scene.materials[0].c0 == 40.0
    a.step(10)
    b.step(10)
    assert b.time == a.time
    np.testing.assert_array_equal(b.positions(), a.positions())
    np.testing.assert_array_equal(b.density(), a.density())


# --- refused folders ---------------------------------------------------------------------
def refusal(folder) -> str:
    with pytest.raises(CheckpointError) as info:
        taisph.Simulation.from_checkpoint(folder)
    message = str(info.value)
    assert isinstance(info.value, ValueError) and "\n" not in message
    return message


def test_an_old_pickled_checkpoint_is_refused_with_its_version(tmp_path):
    folder = tmp_path / "old"
    folder.mkdir()
    (folder / "meta.pickle").write_bytes(pickle.dumps({"version": 3}))
    np.savez(folder / "state.npz", C0=np.zeros(3))
    assert refusal(folder) == (
        f"{folder}: a checkpoint of version 3 or earlier (meta.pickle), this taisph "
        f"({checkpoint.taisph_version()}) reads version {SCHEMA} (meta.json): resume it with the taisph that "
        "wrote it (one from before checkpoint version 4), or rerun")


def test_another_schema_version_is_refused_with_its_version(saved, tmp_path):
    _, out, _, _ = saved
    folder = tmp_path / "newer"
    folder.mkdir()
    for name in ("state.npz", "scene.npz"):
        (folder / name).write_bytes((out / "checkpoint" / name).read_bytes())
    meta = json.loads((out / "checkpoint" / "meta.json").read_text())
    meta["schema"], meta["taisph"] = SCHEMA + 1, "9.9.9"
    (folder / "meta.json").write_text(json.dumps(meta))
    assert refusal(folder) == (
        f"{folder}: checkpoint version {SCHEMA + 1} (written by taisph 9.9.9), this taisph "
        f"({checkpoint.taisph_version()}) reads version {SCHEMA}: resume it with the taisph that wrote it "
        "(version 9.9.9), or rerun")


def test_a_foreign_meta_json_is_refused(tmp_path):
    (tmp_path / "meta.json").write_text(json.dumps({"format": "other-tool", "schema": 2}))
    message = refusal(tmp_path)
    assert message.startswith(f"{tmp_path}: meta.json is not a taisph checkpoint (format 'other-tool', version 2)")
    assert f"reads format 'taisph-checkpoint' version {SCHEMA}: rerun" in message
    (tmp_path / "meta.json").write_text("{not json")
    assert refusal(tmp_path).startswith(f"{tmp_path}: meta.json is not JSON (")


def test_no_folder_or_a_run_folder_is_refused_saying_what_to_resume(saved, tmp_path):
    _, out, _, _ = saved
    missing = tmp_path / "nothing"
    assert refusal(missing) == f"{missing}: no such folder"
    with pytest.raises(FileNotFoundError):  # also a FileNotFoundError, as before
        taisph.Simulation.from_checkpoint(missing)
    assert refusal(out) == f"{out} is a run's output folder: resume {out / 'checkpoint'}"
    assert refusal(tmp_path) == f"{tmp_path} is not a checkpoint folder (no meta.json)"


def test_a_damaged_checkpoint_is_refused_in_one_line(saved, tmp_path):
    _, out, _, _ = saved
    for name in ("state.npz", "scene.npz"):
        (tmp_path / name).write_bytes((out / "checkpoint" / name).read_bytes())
    meta = json.loads((out / "checkpoint" / "meta.json").read_text())
    meta["scene"]["terms"][0]["class"] = "Vorticity"
    (tmp_path / "meta.json").write_text(json.dumps(meta))
    assert refusal(tmp_path) == (
        f"{tmp_path}: a damaged checkpoint of version {SCHEMA}: term 'continuity' of class 'Vorticity': this "
        f"taisph has no such class (it has {', '.join(TERMS)}); "
        "rerun")
    (tmp_path / "scene.npz").unlink()
    assert refusal(tmp_path) == f"{tmp_path}: an incomplete checkpoint (no scene.npz); rerun"


def test_a_checkpoint_interrupted_between_its_two_renames_is_found(saved, tmp_path):
    """save() renames the old checkpoint aside, then the new one in: Ctrl-C between the two
    left only ``checkpoint.old``, and resume said there was no checkpoint. Now read()
    puts the last complete one back."""
    sim, out, _, _ = saved
    shutil.copytree(out / "checkpoint", tmp_path / "checkpoint.old")
    meta, _ = checkpoint.read(tmp_path / "checkpoint")
    assert meta["t_end"] == 0.02 and (tmp_path / "checkpoint" / "meta.json").exists()
    assert not (tmp_path / "checkpoint.old").exists()


def test_a_scene_files_run_checkpoints_and_resumes(tmp_path, capsys):
    """A scene file's wall groups are slices of the particle ids: saving them raised
    TypeError ("cannot be stored as plain data") on the first checkpoint."""
    from taisph.cli import main as cli
    from taisph.scene.catalogue import cases_folder

    out = tmp_path / "out"
    args = ["--t-end", "0.004", "--frames", "2", "--checkpoint-every", "1", "--out", str(out), "--no-progress"]
    assert cli.main([str(cases_folder() / "dam_break_probes_2d.toml"), *args]) == 0
    meta = json.loads((out / "checkpoint" / "meta.json").read_text())
    assert meta["run"]["wall_groups"] and all(isinstance(v, list) for v in meta["run"]["wall_groups"].values())
    assert cli.main(["resume", str(out / "checkpoint"), "--t-end", "0.006", "--no-progress"]) == 0


def test_ctrl_c_while_a_checkpoint_is_written_leaves_the_last_one_whole(saved, tmp_path, monkeypatch):
    """A KeyboardInterrupt inside save() (here raised by the second array file's write; a
    real SIGINT is held back until save() ends) left OUT/checkpoint.tmp behind (CI's SIGINT
    test caught it): now the temporary folder is removed and the last checkpoint stands."""
    sim, out, _, _ = saved
    folder = tmp_path / "checkpoint"
    shutil.copytree(out / "checkpoint", folder)
    before = (folder / "meta.json").read_text()
    savez = np.savez

    def interrupted(path, **arrays):
        if str(path).endswith("scene.npz"):
            raise KeyboardInterrupt
        return savez(path, **arrays)

    monkeypatch.setattr(checkpoint.np, "savez", interrupted)
    with pytest.raises(KeyboardInterrupt):
        checkpoint.save(sim, folder, t_end=0.04, frames_left=1)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["checkpoint"]
    assert (folder / "meta.json").read_text() == before
