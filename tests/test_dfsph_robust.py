"""DFSPH through violent flow (issue 25): the pressure solve converges where it iterates
long, a splash gets no stale pressure, a step whose solve fails is retried with half the
dt, and the guards see what goes wrong (a speed far above the flow's, a clock that
stands still) with a diagnosis, from run() and step() alike. The long runs (dam breaks
to 3 s, the 3D dam break, the still tank for 10 s) are marked slow; docs/dfsph.md
gives their measured values."""

import numpy as np
import pytest

import taisph
from taisph.engine import guards, solvers
from taisph.engine import status as st
from taisph.run.simulation import SimulationError
from test_dfsph import dfsph_scene, mean_compression


def traced_errors(sim):
    """Record the mean error after every iteration of the next solves into a list (plain
    Jacobi iterations: the Chebyshev weights are not set)."""
    stepper = sim.pressure_solve
    errors = []

    def solve(iterate, t_target, tolerance, minimum, maximum, accelerate=False, first=None):
        count = 0
        while True:
            (first if count == 0 and first is not None else iterate)(t_target)
            count += 1
            errors.append(float(stepper.result[0]))
            if (count >= minimum and errors[-1] <= tolerance) or count >= maximum:
                return count, errors[-1]

    stepper._solve = solve
    return errors


def test_a_long_density_solve_converges_without_growing():
    """The solve's matrix is symmetric positive semi-definite (the walls' mirror share in the
    pressure force and in the density rate alike): 3000 Jacobi iterations of one step of
    the dam break at dx = 0.02 (t = 0.11 s) lower the mean density error monotonically to
    below 1e-6 (measured 5.1e-7). With the share in the pressure only, the matrix had
    negative eigenvalues (-0.14 of D^-1 A) at the left wall and the same solve reached
    1.25e-6, then grew to 1.73e-6: a mode the iteration amplifies, which at t = 0.11 s of a
    run with a ramped first dt blew a particle at the wall to 36 m/s."""
    sim = taisph.Simulation(dfsph_scene(dx=0.02))
    sim.run(0.11, frames=1)
    sim.set(dfsph_tolerance=1e-9, dfsph_max_iterations=3000, dfsph_error_bound=1e9)
    errors = traced_errors(sim)
    sim.step(1)
    assert len(errors) == 3000
    assert errors[-1] == min(errors) and errors[-1] < 1e-6, (errors[0], min(errors), errors[-1])
    assert np.all(np.diff(errors[100:]) <= 1e-12)  # no growing mode


def test_a_splash_starts_its_solve_from_zero_pressure():
    """A fluid particle with fewer neighbours than dfsph_min_neighbours (a splash) does not
    keep the last step's pressure as its warm start. In the dam break at dx = 0.01 a
    particle whose one neighbour stood at the support's edge got k = p / rho^2 = 3e5 (its
    factor is huge there); warm-started into the next step and not iterated away (the
    stopping rule is a mean over 20k particles) it kicked the particle from 12 to 15 m/s,
    and on to 200 m/s over the next encounters. Here: a particle of still water moved into
    the air above the tank with k = 1e5 keeps no pressure after a step (with the warm start
    kept, its lone k could never change: no neighbour, no update), while the water keeps
    its warm start."""
    sim = taisph.Simulation(dfsph_scene("hydrostatic_tank", dx=0.05))
    sim.run(0.05, frames=1)
    q = sim.solver.layout.q
    vec, sca, ints = sim.state.memory_order()
    fluid = ints[q.kind] == taisph.FLUID
    lone = np.flatnonzero(fluid)[0]
    top = vec[q.position][fluid, 1].max()
    vec[q.position][lone] = [0.5, top + 0.5]
    vec[q.velocity][lone] = 0.0
    sca[q.kappa][lone] = 1e5
    sim.state.set_state(vec, sca, ints)
    sim.step(1)
    kappa, pressure, ids = sim.quantity("kappa"), sim.pressure(), sim.ids()
    pid = ints[q.id][lone]
    assert kappa[pid] == 0.0 and pressure[pid] == 0.0
    assert np.linalg.norm(sim.velocities()[pid] - sim.dt * np.array([0.0, -9.81])) < 1e-9  # gravity only
    assert np.count_nonzero(kappa[sim.fluid] > 0) > 0.8 * sim.fluid.sum()


def test_a_step_whose_solve_fails_is_retried_with_half_the_dt():
    """With 3 iterations at most, 10 of the dam break's 61 steps to 0.3 s (dx = 0.04) end
    beyond 10 times the tolerance: each is tried again with half the dt, and the run gets
    to its end (the summary counts them), mass conserved; with no retries it stops."""
    summary = taisph.Simulation(dfsph_scene(dx=0.04), dfsph_max_iterations=3).run(0.3, frames=1)
    ps = summary.pressure_solve
    assert summary.sim_time == pytest.approx(0.3)
    assert ps["retries"] >= 1
    assert f"{ps['retries']} steps retried with half the dt" in str(summary)
    assert summary.fluid_mass == pytest.approx(dfsph_scene(dx=0.04).mass[dfsph_scene(dx=0.04).kind == 0].sum(),
                                               rel=1e-12)
    with pytest.raises(SimulationError):
        taisph.Simulation(dfsph_scene(dx=0.04), dfsph_max_iterations=3, dfsph_retries=0).run(0.3, frames=1)


def test_retries_that_do_not_help_end_in_the_diagnosis(tmp_path):
    """A tolerance no solve reaches: the step is tried dfsph_retries + 1 times, then the run
    stops with the diagnosis, which says so."""
    sim = taisph.Simulation(dfsph_scene(dx=0.04), dfsph_tolerance=1e-12, dfsph_max_iterations=4,
                            dfsph_error_bound=1.0, dfsph_retries=2)
    with pytest.raises(SimulationError) as err:
        sim.run(0.1, out=tmp_path)
    assert "after 2 retries of the step, each with half the dt" in str(err.value)
    assert err.value.report["pressure_solve"]["retries"] == 2
    assert sim.pressure_solve.stats.retries == 2


def test_the_speed_guard_stops_a_particle_far_faster_than_the_flow(tmp_path):
    """max_speed (default under DFSPH: the largest c0, 10x the flow's speed in the cases):
    a particle above it stops the run with what, where, when, the remedy and the .vtu
    evidence; from step() as from run(). Here the limit is set to 1 m/s, which the dam
    break's surge passes within 0.2 s."""
    scene = dfsph_scene(dx=0.04)
    limit = solvers.of(scene).max_speed(scene)  # the method's default (Method.max_speed)
    assert guards.max_speed(scene, taisph.Simulation(scene).controls, limit) == pytest.approx(
        max(m.c0 for m in scene.materials))
    wcsph = taisph.cases.dam_break(dx=0.04)
    assert guards.max_speed(wcsph, taisph.engine.timestep.Controls(), solvers.of(wcsph).max_speed(wcsph)) == 0.0  # off
    for advance in ("run", "step"):
        sim = taisph.Simulation(dfsph_scene(dx=0.04), max_speed=1.0)
        with pytest.raises(SimulationError) as err:
            if advance == "run":
                sim.run(0.3, out=tmp_path / advance)
            else:
                for _ in range(200):
                    sim.step(5)
        message = str(err.value)
        assert "speed above max_speed" in message and "above max_speed = 1 m/s" in message, message
        assert "--max-speed" in message and "--dt-max" in message
        speeds = [np.linalg.norm(p["velocity"]) for p in err.value.report["particles"]]
        assert min(speeds) > 1.0
        assert any(f.name.endswith("_offending.vtu") for f in err.value.files)
        assert err.value.report["time"] < 0.3


def test_a_clock_that_stands_still_is_diagnosed():
    """A step too small to advance the clock (here dt_max = 1e-300 s at t = 0.01 s) stops
    with the diagnosis, naming the fastest particles, not a bare RuntimeError."""
    sim = taisph.Simulation(dfsph_scene(dx=0.04))
    sim.run(0.01, frames=1)
    sim.set(dt_max=1e-300)
    with pytest.raises(SimulationError) as err:
        sim.step(3)
    assert "time step collapsed" in str(err.value)
    assert len(err.value.report["particles"]) == 5
    assert err.value.report["codes"] == ["time step collapsed"]
    assert sim.state.read_flag(st.CODES) & st.STALLED


def test_container_layers_follow_each_wall_without_holes():
    """Dummy-wall layers behind a polyline container (geometry.container_layers): along a
    box they are the tank's lattice layers (wall_layers), but for the far corner points;
    behind the 45 degree incline of drop_on_incline they lie on the incline's own lattice
    (smooth), no two closer than 0.7 dx, none on the fluid's side, and every point of the
    wall side within a support (2.6 dx) of the outline has a wall particle within 0.75 dx."""
    from taisph.geometry import container_layers, wall_layers

    dx = 0.02
    box = container_layers([(0, 1), (0, 0), (1, 0), (1, 1)], dx, 3)
    ref = wall_layers([0, 0], [1, 1], dx, 3)
    gap = np.linalg.norm(box[:, None] - ref[None], axis=2)
    assert gap.min(axis=1).max() < 1e-12  # every one is a lattice layer point
    missed = ref[gap.min(axis=0) > 1e-12]
    corners = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert len(missed) == 2 and np.linalg.norm(missed[:, None] - corners[None], axis=2).min(axis=1).min() > 3 * dx
    incline, floor, height = 1.6, 1.0, 2.2
    outline = [(0, height), (0, incline), (incline, 0), (incline + floor, 0), (incline + floor, height)]
    w = container_layers(outline, dx, 3)
    near = np.linalg.norm(w[:, None] - w[None], axis=2) + np.eye(len(w)) * 1e9
    assert near.min() > 0.7 * dx  # where the lattices of two walls join (0.78 dx measured)
    above = (w[:, 0] > 0) & (w[:, 0] < incline + floor) & (w[:, 1] > np.maximum(incline - w[:, 0], 0))
    assert not above.any()
    on_plane = (w[:, 0] > 0.3) & (w[:, 0] < incline - 0.3)
    depth = (incline - w[on_plane, 0] - w[on_plane, 1]) / np.sqrt(2)
    assert np.allclose(np.sort(np.unique(np.round(depth / dx, 9))), [0.5, 1.5, 2.5])  # rows of the incline
    rng = np.random.default_rng(1)
    s, d = rng.uniform(0.1, incline * np.sqrt(2) - 0.1, 2000), rng.uniform(0, 2.6 * dx, 2000)
    probe = np.column_stack([s / np.sqrt(2), incline - s / np.sqrt(2)]) - d[:, None] * np.array([1, 1]) / np.sqrt(2)
    assert np.linalg.norm(probe[:, None] - w[None], axis=2).min(axis=1).max() < 0.75 * dx


def test_drop_on_incline_runs_with_dfsph_on_dummy_walls():
    """drop_on_incline(solver="dfsph") (and --solver dfsph) builds dummy walls, which DFSPH
    needs, and runs to its end at dx = 0.02: no fluid particle below the incline or
    outside the container, the mean compression within 0.1 % at the end, the energy
    (kinetic + potential) not growing (from 2087 J/m it falls to 1766, measured; WCSPH
    with its Lennard-Jones walls, to 1439), mass kept."""
    from taisph.cases.drop_on_incline import height_above_plane

    scene = taisph.cases.drop_on_incline(dx=0.02, solver="dfsph")
    assert scene.solver == "dfsph" and "dummy_walls" in [t.name for t in scene.terms]
    with pytest.raises(ValueError, match="needs walls = 'dummy'"):
        taisph.cases.drop_on_incline(solver="dfsph", walls="lj")
    sim = taisph.Simulation(scene)

    def energy():
        f = sim.fluid
        m, v, x = sim.masses()[f], sim.velocities()[f], sim.positions()[f]
        return float(np.sum(m * (0.5 * (v * v).sum(axis=1) + 9.81 * x[:, 1])))

    e0 = energy()
    summary = sim.run(0.7, frames=1)
    x = sim.positions()[sim.fluid]
    assert summary.removed == 0 and sim.fluid.sum() == scene.n_fluid
    assert height_above_plane(x).min() > 0 and x[:, 1].min() > 0 and 0 < x[:, 0].min() and x[:, 0].max() < 2.6
    rho = sim.density()[sim.fluid]
    assert np.mean(np.maximum(rho / 1000.0 - 1, 0)) < 0.001
    assert energy() < e0


# --- runs to the end with the defaults (issue 25) --------------------------------------------
# The dam break's fastest physical speed: the surge 2 sqrt(g H) = 8.9 m/s plus the run-up at the
# right wall; WCSPH's fastest frame at dx = 0.01 is ~12 m/s. A rogue particle (the 200 m/s)
# would stand far above 1.5 times it.
PHYSICAL_SPEED = 12.0


class StepMaxima:
    """A run writer: the largest fluid speed of every step (the device's maximum of |v|, DFSPH's
    signal speed, read after each step)."""

    every = 1

    def __init__(self):
        self.speed = 0.0

    def on_start(self, sim):
        pass

    def on_steps(self, sim):
        self.speed = max(self.speed, sim.state.read(st.MAX_SIGNAL))

    def on_frame(self, sim, k):
        pass


def run_dam_break_to_the_end(dx, t_end=3.0, frames=30):
    """A DFSPH dam break with the defaults to t_end: (summary, largest step speed, frame
    compressions) where a frame's compression is the mean over the fluid of max(rho/rho0 - 1, 0)."""
    sim = taisph.Simulation(dfsph_scene(dx=dx))
    maxima, compression = StepMaxima(), []
    summary = sim.run(t_end, frames=frames, callback=lambda s: compression.append(mean_compression(s)),
                      writers=[maxima])
    return sim, summary, maxima.speed, compression


@pytest.mark.parametrize("dx", [0.04, pytest.param(0.02, marks=pytest.mark.slow),
                                pytest.param(0.01, marks=pytest.mark.slow)])
def test_dam_break_runs_to_3_s_with_physical_speeds_and_no_compression(dx):
    """dam_break --solver dfsph with no other option to t = 3 s (through the impact, the
    run-up and the wave's return): no step's fastest fluid particle above 1.5 x the
    flow's fastest physical speed (measured with the defaults: 9.9, 11.9, 13.3 m/s at
    dx = 0.04, 0.02, 0.01; 13.7 at 0.005, docs/dfsph.md), the mean compression within
    0.075 % in every frame (3x the measured: 0.0254 % at dx = 0.04, 2026-12-07, `pytest -n 0
    -s tests/test_dfsph_robust.py -k no_compression` with a print, ~30 s; at most 0.024 %
    quoted before for the three; the slow spacings' bar tightened from 0.1 % without a
    rerun), and the fluid mass accounted (fluid + removed = initial, 1e-12). The issue's
    run at dx = 0.01 had a particle at 3.5e5 m/s near t = 0.99 s."""
    sim, summary, speed, compression = run_dam_break_to_the_end(dx)
    assert summary.sim_time == pytest.approx(3.0)
    assert speed <= 1.5 * PHYSICAL_SPEED, speed
    assert max(compression) <= 7.5e-4, max(compression)
    initial = float(sim.scene.mass[sim.scene.kind == taisph.FLUID].sum())
    assert summary.fluid_mass + summary.removed_mass == pytest.approx(initial, rel=1e-12)


@pytest.mark.parametrize("dx", [0.02, pytest.param(0.01, marks=pytest.mark.slow)])
def test_the_step_count_does_not_depend_on_writing_frames(dx):
    """To t = 1 s, the run with 20 frames and the run without take step counts within 7 %
    of each other (the issue: 13 301 steps without frames, 1 748 with: a rogue particle in
    one of them throttled its step). Measured: at dx = 0.02 494 and 494 steps (2026-12-07,
    `pytest -n 0 -s tests/test_dfsph_robust.py -k does_not_depend_on_writing` with a print);
    at dx = 0.01 within 1.8-2.2 % (slow, not rerun); the bar is 3x the larger."""
    counts = [taisph.Simulation(dfsph_scene(dx=dx)).run(1.0, frames=frames).steps for frames in (0, 20)]
    assert abs(counts[1] / counts[0] - 1.0) <= 0.07, counts


@pytest.mark.slow
def test_dam_break_3d_runs_to_2_s():
    """dam_break_3d --solver dfsph at its default spacing to t = 2 s: no step faster than 1.5 x
    the flow's speed (measured 10.9 m/s), compression within 0.1 % (0.006 %), mass accounted."""
    sim = taisph.Simulation(dfsph_scene("dam_break_3d"))
    maxima, compression = StepMaxima(), []
    summary = sim.run(2.0, frames=10, writers=[maxima], callback=lambda s: compression.append(mean_compression(s)))
    assert summary.sim_time == pytest.approx(2.0)
    assert maxima.speed <= 1.5 * PHYSICAL_SPEED and max(compression) <= 1e-3
    initial = float(sim.scene.mass[sim.scene.kind == taisph.FLUID].sum())
    assert summary.fluid_mass + summary.removed_mass == pytest.approx(initial, rel=1e-12)
