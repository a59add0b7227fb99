"""Looking never changes the answer: a run written as 1 frame or as 100, with probes
sampled every step, a checkpoint every frame and a callback reading the state, reaches
the same final state bit for bit (deterministic mode), for a free-surface case (the dam
break) and a body case (the floating box). Each writer is called at the first step that
reaches its output time, with that step's own time (taisph.Simulation.run).

Before this, steps were shortened to land on every output time: with 100 frames the dam
break took other steps than with 1, and the final states differed (the solitary wave's
crest moved by 6 % with ``--frames 1``, issue 50)."""

import numpy as np
import pytest

import taisph
from taisph.probes import Probes, body, pressure

T_END = 0.05


def _final_state(scene, frames, tmp_path=None, look=False):
    sim = taisph.Simulation(scene, deterministic=True)
    times = []
    writers, out = [], None
    if look:
        probes = [pressure("p", scene.probe_point)] + [body(b.name) for b in scene.bodies]
        writers = [Probes(probes, walls={}, path=tmp_path / "probes.csv")]
        out = tmp_path

    def callback(s):
        s.positions(), s.pressure()  # reading the state must not change it
        times.append((s.time, s.dt))

    try:
        sim.run(T_END, frames=frames, out=out, callback=callback, checkpoint_every=1 if look else None,
                writers=writers)
    finally:
        for w in writers:
            w.close()
    state = (sim.time, sim.steps, sim.positions(), sim.velocities(), sim.density())
    sim.close()
    return state, times


@pytest.fixture(params=["dam_break", "floating_box"])
def scene_factory(request):
    def make():
        if request.param == "dam_break":
            scene = taisph.cases.dam_break(dx=0.04)
            scene.probe_point = (0.5, 0.2)
        else:
            scene = taisph.cases.floating_box(dx=0.04)
            scene.probe_point = (0.2, 0.5)
        return scene
    return make


def test_frames_probes_checkpoints_and_callbacks_leave_the_trajectory_unchanged(scene_factory, tmp_path):
    (t1, steps1, *arrays1), _ = _final_state(scene_factory(), frames=1)
    (t100, steps100, *arrays100), times = _final_state(scene_factory(), frames=100, tmp_path=tmp_path, look=True)
    assert t1 == t100 == T_END  # the run's end is the one time a step is shortened to reach
    assert steps1 == steps100
    for a, b in zip(arrays1, arrays100):
        np.testing.assert_array_equal(a, b)
    assert (tmp_path / "checkpoint" / "meta.json").exists() and (tmp_path / "probes.csv").exists()
    # each writer was called at the first step reaching its output time, with that step's time
    targets = [T_END * (k + 1) / 100 for k in range(100)]
    late = [(t - target) / dt for (t, dt), target in zip(times, targets)]
    assert all(t >= target - 1e-12 for (t, _), target in zip(times, targets))
    assert max(late) <= 1.0 + 1e-9, f"a writer was called more than one step after its output time: {max(late)}"
