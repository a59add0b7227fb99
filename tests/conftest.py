import os

import numpy as np
import pytest

# Tests run on the CPU; TAISPH_TEST_PRECISION=f32 runs the suite in single precision.
PRECISION = os.environ.get("TAISPH_TEST_PRECISION", "f64")


@pytest.fixture(scope="session", autouse=True)
def taichi_runtime():
    from taisph.engine import runtime

    return runtime.init(arch="cpu", precision=PRECISION)


@pytest.fixture
def rng():
    return np.random.default_rng(20131218)


@pytest.fixture
def at_output_times():
    """A check that frames were written at their output times: at the first step reaching
    each (taisph.Simulation.run shortens no step for them, only the last for the end), so
    each frame's time is at or after its output time by less than one step. `step`: a
    bound on the run's steps (the dam break at dx = 0.1 m: 0.56-0.83 ms over its first
    0.05 s, measured 2026-12-07)."""

    def check(times, targets, step=1e-3):
        assert len(times) == len(targets), (times, targets)
        for t, target in zip(times, targets):
            assert target - 1e-12 * max(1.0, target) <= t < target + step, (t, target)
        assert times[-1] == pytest.approx(targets[-1], abs=1e-12)  # the end is landed on exactly

    return check


@pytest.hookimpl(tryfirst=True)  # before `-m` deselects: `pytest -m validation` runs the tier
def pytest_collection_modifyitems(config, items):
    """Mark the validation tier (tests/validation_tier.py: the physical claims CI checks
    against references, at the cheapest resolution at which they mean something)."""
    from validation_tier import TIER

    for item in items:
        if item.nodeid.split("[")[0] in TIER and item.get_closest_marker("slow") is None:
            item.add_marker(pytest.mark.validation)  # a slow parametrisation stays in the slow suite
