"""A sweep that fails leaves its folder usable (issue 50: "a failed sweep leaves
sweep.csv/json/md behind, and the next, different sweep into that folder is refused"),
and ``sweep --help`` takes its defaults from the code (it said Courant 0.25 where
dam_break runs 0.4, and cut its description mid-word)."""

import logging
import re

import pytest

import taisph
from taisph.cli.sweep import DESCRIPTION
from taisph.cli.main import main as cli
from taisph.messages import TaisphWarning
from taisph.sweeps import SweepError

distributed = pytest.importorskip("distributed", reason="the sweep extra: pip install 'taisph[sweep]'")

CASE = "hydrostatic_tank"
FILES = ["sweep.csv", "sweep.json", "sweep.md"]


class InterruptedClient:
    """A cluster that takes the sweep's first run and is then interrupted (Ctrl-C)."""

    def wait_for_workers(self, n, timeout=None):
        pass

    def nthreads(self):
        return {"tcp://127.0.0.1:1": 1}

    def submit(self, *args, **kwargs):
        raise KeyboardInterrupt


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=logging.ERROR) as cluster, distributed.Client(cluster) as c:
        yield c


def files(folder):
    return sorted(p.name for p in folder.iterdir())


def test_a_failed_sweep_leaves_nothing_and_the_folder_takes_another(client, tmp_path):
    """An interrupted sweep (before any run finished) leaves no sweep.csv/json/md; a sweep
    whose every run failed (a point raising: dx too large for the tank) leaves its table,
    and a different sweep into that folder runs (with a warning) and replaces it; a
    folder with a finished run still refuses a different sweep."""
    folder = tmp_path / "sweep"
    options = dict(out=folder, validate=False, t_end=0.01, progress=False)
    with pytest.raises(KeyboardInterrupt):
        taisph.sweep(CASE, vary={"dx": [0.1]}, client=InterruptedClient(), **options)
    assert not folder.exists()  # the folder it made, gone again
    folder.mkdir()
    with pytest.raises(KeyboardInterrupt):
        taisph.sweep(CASE, vary={"dx": [0.1]}, client=InterruptedClient(), **options)
    assert files(folder) == []  # a folder that was there stays, empty

    failed = taisph.sweep(CASE, vary={"dx": [0.8]}, client=client, **options)  # the tank has no room for dx
    assert failed[0]["status"].startswith("failed: ParameterError: hydrostatic_tank: dx = 0.8 m")
    assert files(folder) == FILES
    with pytest.warns(TaisphWarning, match="held another sweep .* without a finished run"):
        rows = taisph.sweep(CASE, vary={"kernel": ["wendland"]}, dx=0.1, client=client, **options)
    assert [r["status"] for r in rows] == ["ok"]
    assert "kernel" in (folder / "sweep.csv").read_text().splitlines()[0]
    assert "dx=0.8" not in (folder / "sweep.md").read_text()
    with pytest.raises(SweepError, match="holds another sweep"):
        taisph.sweep(CASE, vary={"dx": [0.1]}, client=client, **options)
    assert files(folder) == FILES


def help_text(capsys, argv) -> str:
    """What ``python -m taisph ARGV`` prints, its whitespace collapsed (help exits with 0)."""
    try:
        code = cli(argv)
    except SystemExit as done:
        code = done.code
    assert code in (0, None)
    return " ".join(capsys.readouterr().out.split())


def test_sweep_help_takes_its_defaults_from_the_code(capsys):
    """The description is whole; the Courant number's default is the case's own (dam_break:
    0.4, shown by sweep dam_break --help), else the engine's; the cases with a reference are
    those the validations have."""
    text = help_text(capsys, ["sweep", "--help"])
    assert " ".join(DESCRIPTION.split()) in text and "a parameter swee." not in text
    assert "Courant number of the adaptive step; default: the case's or scene file's own" in text
    assert "(default 0.25, or the scene file's)" not in text
    assert re.search(r"A case with a reference \(dam_break, hydrostatic_tank, .*cylinder\)", text)
    text = help_text(capsys, ["sweep", "dam_break", "--vary", "dx=0.1,0.05", "--help"])
    assert "else 0.25; DFSPH 0.5; this case: 0.4" in text and "this case: 0.02 m" in text
