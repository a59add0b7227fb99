"""What a new user meets (issue 24): standard output carries results only, a missing
backend is a one-line error, taisph's warnings are one line on the command line, and a
diagnosis survives a failure to write its evidence."""

import os
import subprocess
import sys

import pytest

import taisph
from taisph import messages
from taisph.engine import runtime
from taisph.geometry import lattice
from taisph.run.simulation import SimulationError
from taisph.terms import Continuity, Gravity, PressureGradient


def run_python(*args, timeout=300):
    """A fresh Python, without the switch importing taisph.messages set in this process
    (a user's environment does not have it)."""
    env = {k: v for k, v in os.environ.items() if k != "ENABLE_TAICHI_HEADER_PRINT"}
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=timeout, env=env)


def test_importing_taisph_prints_nothing_on_stdout():
    """Taichi printed its banner ("[Taichi] version 1.7.4, ...") to standard output when
    taisph imported it, so ``$(python -c ...)`` captured it."""
    done = run_python("-c", "import taisph")
    assert done.returncode == 0, done.stderr
    assert done.stdout == ""


def test_starting_taichi_prints_nothing_on_stdout():
    """ti.init printed "[Taichi] Starting on arch=x64" to standard output."""
    done = run_python("-c", "import taisph; print('RESULT'); taisph.Simulation(taisph.cases.dam_break(dx=0.2)).close()")
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("RESULT\n")[1] == ""


@pytest.mark.parametrize("arch", ["cuda", "vulkan"])
def test_a_missing_backend_is_a_one_line_error(arch):
    """Without the device, --arch cuda printed Taichi's log lines and a 24-line traceback
    before its message, and exited 1."""
    if runtime.available(arch):
        pytest.skip(f"this machine has a {arch} device")
    done = run_python("-m", "taisph", "dam_break", "--arch", arch, "--no-output", "--t-end", "0.001")
    assert done.returncode == 2, done.stderr
    lines = done.stderr.splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("taisph: error: ") and f"arch={arch}" in lines[0] and "--arch cpu" in lines[0]


def test_a_missing_backend_is_a_value_error_and_keeps_the_live_runtime():
    live = runtime.current()
    for arch in ("cuda", "vulkan", "metal"):
        if runtime.available(arch):
            continue
        with pytest.raises(runtime.BackendUnavailable, match=f"arch={arch} was requested") as err:
            runtime.init(arch=arch)
        assert isinstance(err.value, ValueError) and isinstance(err.value, RuntimeError)
    assert runtime.current() is live and runtime.is_current(live)


def test_taisph_warnings_are_one_line_once_installed():
    """Python printed a warning with its file path, line number and source line
    (".../taisph/run/simulation.py:253: RuntimeWarning: fixed dt = ..." and the line)."""
    code = ("import warnings\nfrom taisph import messages\nmessages.install()\nmessages.install()\n"
            "warnings.warn('fixed dt = 0.002 s is above the stability limit', messages.TaisphRuntimeWarning)\n"
            "warnings.warn('something else', UserWarning)\n")
    done = run_python("-c", code)
    assert done.returncode == 0, done.stderr
    err = done.stderr.splitlines()
    assert err[0] == "taisph: warning: fixed dt = 0.002 s is above the stability limit"
    assert err[1] == "<string>:6: UserWarning: something else"  # other warnings as before
    assert len(err) == 2
    assert issubclass(messages.TaisphRuntimeWarning, RuntimeWarning)  # pytest.warns(RuntimeWarning) still matches
    assert issubclass(messages.TaisphRuntimeWarning, messages.TaisphWarning)
    assert issubclass(messages.TaisphWarning, UserWarning)


def falling_block():
    """A block falling out of an open domain: the 'left the domain' guard trips."""
    dx = 0.1
    scene = taisph.Scene("block", dim=2, dx=dx, smoothing_length=1.3 * dx, domain=([0, 0], [2, 2]),
                         materials=[taisph.Material(c0=20.0)], terms=[Continuity(), PressureGradient(), Gravity()])
    scene.add_fluid(lattice([0.5, 1.0], [1.1, 1.6], dx))
    return scene


def test_the_diagnosis_survives_evidence_that_cannot_be_written(monkeypatch, tmp_path):
    """An error while writing the evidence replaced the SimulationError: the user got an
    OSError and lost the diagnosis."""
    from taisph.run import vtk

    write_vtu = vtk.write_vtu

    def unwritable_evidence(path, *args, **kwargs):  # frames are written, the evidence is not
        if "_last_good" in str(path) or "_offending" in str(path):
            raise OSError(28, "No space left on device", str(path))
        return write_vtu(path, *args, **kwargs)

    monkeypatch.setattr(vtk, "write_vtu", unwritable_evidence)
    sim = taisph.Simulation(falling_block())
    with pytest.raises(SimulationError) as err:
        sim.run(1.0, frames=2, out=tmp_path)
    sim.close()
    message = str(err.value)
    assert "simulation stopped at step" in message and "left the domain" in message and "likely cause" in message
    assert f"the evidence could not be written to {tmp_path}: OSError" in message
    assert "No space left on device" in message
    assert err.value.files == [] and isinstance(err.value.__cause__, OSError)
    assert err.value.report["codes"] == ["left the domain"]
    assert (tmp_path / "block_00000.vtu").exists()
