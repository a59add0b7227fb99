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
