"""The drain (taisph/terms/drain.py), docs/architecture.md's worked example of a subsystem:
mass is conserved exactly as fluid + drained, nothing fluid stays in the box, water flows
into it, and a scene without it compiles none of it."""

import numpy as np
import pytest

import taisph
from taisph.engine import assembly, kernels
from taisph.terms import Drain

LO, HI = (0.0, 0.0), (0.25, 0.25)  # the tank's bottom-left corner (water 1.0 x 0.5 m)


def drained_tank():
    scene = taisph.cases.hydrostatic_tank()
    scene.terms.append(Drain(drain_lo=LO, drain_hi=HI))
    return scene


def inside(positions):
    return np.all((positions >= np.array(LO)) & (positions <= np.array(HI)), axis=1)


def test_a_drain_keeps_fluid_plus_drained_mass_and_empties_its_box():
    """Initial fluid mass = fluid mass + drained mass to round-off (1e-12 relative) after
    every batch; no fluid particle inside the box after a step; and water keeps flowing in
    (the column above the hole falls into it): after the first step has emptied the box of
    the water that started there, the drained mass grows by at least a tenth of it again."""
    scene = drained_tank()
    fluid = scene.kind == taisph.FLUID
    initial = float(scene.mass[fluid].sum())
    in_box = float(scene.mass[fluid & inside(scene.position)].sum())
    sim = taisph.Simulation(scene, deterministic=True)
    first = Drain.mass_drained(sim)  # the bootstrap step's removal: the water that started there
    assert first == pytest.approx(in_box, rel=1e-12) and first > 0.0
    for _ in range(4):
        sim.step(100)
        assert sim.total_mass() + Drain.mass_drained(sim) == pytest.approx(initial, rel=1e-12)
        assert not inside(sim.positions()[sim.fluid]).any()
    assert Drain.mass_drained(sim) > 1.1 * first


def test_a_drain_moves_at_runtime_and_is_compiled_only_where_listed():
    """Moving the box is a parameter change (no recompilation); a scene without a drain
    traces none of its code."""
    def traced(scene):
        assembly._cache.clear()  # a fresh compilation
        kernels.TRACED.clear()
        sim = taisph.Simulation(scene)
        sim.step(2)
        return sim, {name for name, _ in kernels.TRACED}

    assert "drain" not in traced(taisph.cases.hydrostatic_tank())[1]
    sim, names = traced(drained_tank())
    assert "drain" in names
    compiled = sim.solver.compiled_count()
    sim.set(drain_lo=(0.5, 0.0), drain_hi=(0.75, 0.25))
    before = Drain.mass_drained(sim)
    sim.step(2)
    assert Drain.mass_drained(sim) > before  # the water under the new box went
    assert sim.solver.compiled_count() == compiled


def test_a_drain_refuses_an_empty_box():
    scene = taisph.cases.hydrostatic_tank()
    scene.terms.append(Drain(drain_lo=(0.3, 0.0), drain_hi=(0.2, 0.25)))
    with pytest.raises(ValueError, match="drain_lo must be below drain_hi"):
        taisph.Simulation(scene)
