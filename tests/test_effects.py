"""Only the effects a scene lists are simulated: their code is traced into the kernels,
nothing else, and only their per-particle quantities take memory."""

import subprocess
import sys

import numpy as np
import pytest

import taisph
from taisph.engine import assembly as solver, kernels
from taisph.terms import Continuity, PressureGradient


def bare_scene(dim=2):
    """Water with continuity and pressure only: no walls, viscosity or gravity."""
    scene = taisph.Scene("bare", dim=dim, dx=0.1, smoothing_length=0.13, domain=(np.zeros(dim), np.ones(dim)),
                         terms=[Continuity(), PressureGradient()], materials=[taisph.Material(c0=10.0)])
    scene.add_fluid(np.random.default_rng(1).uniform(0.2, 0.8, size=(50, dim)))
    return scene


def traced_while(build):
    solver._cache.clear()  # force a fresh compilation
    kernels.TRACED.clear()
    build()
    return set(kernels.TRACED)


def test_unlisted_terms_are_not_compiled():
    bare = traced_while(lambda: taisph.Simulation(bare_scene()).step(1))
    assert bare == {("continuity", "pair"), ("pressure", "pair"), ("pressure", "derive"), ("tait", "eos")}
    full = traced_while(lambda: taisph.Simulation(taisph.cases.dam_break(dx=0.2, seed_physics=True)).step(1))
    assert {("artificial_viscosity", "pair"), ("lennard_jones_wall", "pair"), ("gravity", "particle")} <= full
    assert bare < full


def test_a_dfsph_kernel_has_no_equation_of_state_and_a_wcsph_kernel_no_dfsph_pass():
    """Scene(solver="dfsph"): the pressure solve replaces the Tait equation, continuity,
    the pressure gradient, density diffusion and the dummy walls' extrapolation; the
    non-pressure terms stay. The weakly compressible step traces no DFSPH pass."""
    wcsph = traced_while(lambda: taisph.Simulation(taisph.cases.dam_break(dx=0.2)).step(1))
    assert ("tait", "eos") in wcsph and ("dummy_walls", "pass") in wcsph
    assert not {name for name, _ in wcsph} & {"dfsph", "incompressible"}
    scene = taisph.cases.dam_break(dx=0.2)
    scene.solver = "dfsph"
    dfsph = traced_while(lambda: taisph.Simulation(scene).step(1))
    # (the divergence solve compiles when it first has work: not in a first step from rest)
    assert {("dfsph", "density"), ("dfsph", "density solve"), ("artificial_viscosity", "pair"),
            ("gravity", "particle")} <= dfsph
    names = {name for name, _ in dfsph}
    assert not names & {"tait", "continuity", "pressure", "density_diffusion", "dummy_walls"}


def test_the_record_of_what_was_traced_stays_bounded():
    """kernels.TRACED holds each (term, role) once: compiling the same configuration
    again (a fresh solver, fresh fields) adds nothing to it."""
    first = traced_while(lambda: taisph.Simulation(bare_scene()).step(1))
    solver._cache.clear()
    taisph.Simulation(bare_scene()).step(1)
    assert kernels.TRACED == first


def test_unlisted_terms_take_no_memory():
    """The per-particle rows are those of the listed terms: the dam break's viscosity
    and walls add no row (they need none), the bare scene stores exactly the base
    quantities, the predictor-corrector's last rates and the EOS's sound speed."""
    bare = taisph.Simulation(bare_scene())
    L = bare.solver.layout
    assert L.vectors == ("position", "velocity", "acc_prev")
    assert L.scalars == ("density", "pressure", "mass", "d_density_prev", "sound_speed", "p_over_rho2")
    lists = (2 * 8 + 4 + 4 * bare.state.list_capacity) if bare.solver.lists else 0  # x_ref, count, entries
    assert bare.bytes_per_particle() == 3 * (2 * 8 * 3 + 8 * 6 + 4 * 3) + 4 + lists
    euler = bare_scene()
    euler.integrator = "euler"
    assert "acc_prev" not in taisph.Simulation(euler).solver.layout.vectors


def test_help_and_summary_list_the_active_effects(capsys):
    from taisph.cli import main as cli

    with pytest.raises(SystemExit):
        cli.main(["dam_break", "--help"])
    out = capsys.readouterr().out
    assert "effects (compiled in):" in out and "dummy_walls" in out and "density_diffusion" in out
    assert cli.main(["dam_break", "--dx", "0.2", "--t-end", "0.001", "--frames", "1", "--no-output",
                     "--no-progress"]) == 0
    assert "effects: continuity(walls), pressure(walls), artificial_viscosity" in capsys.readouterr().out


def test_gpu_backends_are_wired_and_fail_clearly_without_a_device():
    """--arch cuda / vulkan select Taichi's GPU backends; on a machine without one the
    run stops with a message saying so (run in a subprocess: re-initialising Taichi
    would reset this test process)."""
    for arch in ("cuda", "vulkan"):
        code = ("import taisph, sys\n"
                f"try:\n    taisph.Simulation(taisph.cases.dam_break(dx=0.2), arch='{arch}')\n"
                "except RuntimeError as e:\n    print('REFUSED', e); sys.exit(0)\n"
                "print('RAN ON', taisph.engine.runtime.current().arch)\n")
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
        assert out.returncode == 0, out.stderr
        if "RAN ON" in out.stdout:  # a machine with that GPU
            assert f"RAN ON {arch}" in out.stdout
        else:
            assert f"arch={arch} was requested but Taichi could not start it" in out.stdout
