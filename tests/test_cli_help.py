"""Help texts (issue 50, item 8): ``list`` does not cut a description mid-word; every
case's ``--help`` ends with examples of that case (they all were dam_break's) and says
what each ``--set`` parameter is, with its unit, beside its range; the ``frames`` range
and ``--frames 0`` agree; ``plot`` is dispatched to taisph.cli.plot."""

import inspect
import re
import sys
import types

import pytest

from taisph.cli import case as cli_case
from taisph.cli import case_help
from taisph.cli import main as cli
from taisph.scene import catalogue, parameters

CASES = sorted(catalogue.registry())


def help_text(name: str) -> str:
    return cli_case.build_parser(name).format_help()


@pytest.mark.parametrize("name", CASES)
def test_each_cases_help_ends_with_its_own_examples(name):
    text = help_text(name)
    examples = text.rsplit("examples:\n", 1)[1]
    commands = [line.split("#")[0].split() for line in examples.splitlines() if line.startswith("  python -m taisph")]
    assert len(commands) >= 4
    for words in commands:
        assert words[3] in (name, "resume"), words  # python -m taisph NAME ... / resume ...
    assert f"OUT/{name}.pvd" in examples
    assert "dam_break" not in examples or name.startswith("dam_break")


def test_the_coarser_example_builds():
    """The examples' --dx is one the case builds at (twice its default where it can)."""
    for name in CASES:
        found = re.search(rf"python -m taisph {name} --dx (\S+)", help_text(name))
        if found:
            catalogue.find(name)(dx=float(found.group(1)))


@pytest.mark.parametrize("name", CASES)
def test_every_parameter_has_a_meaning(name):
    """Each parameter's range is followed by what it is; a parameter the case's docstring
    defines with its unit (``name (unit): ...``) shows that definition."""
    meanings = case_help.parameter_meanings(name)
    assert set(meanings) == set(catalogue.parameters(name))
    assert all(len(text) > 8 for text in meanings.values()), meanings
    listing = case_help.describe_parameters(name).splitlines()
    for p in catalogue.parameters(name).values():
        at = next(k for k, line in enumerate(listing) if line.startswith(f"  {p.name} = "))
        assert listing[at].rstrip().endswith(p.range.describe())
        assert listing[at + 1].startswith("      ") and listing[at + 1].strip(), p.name


def test_meanings_say_units():
    dam = case_help.parameter_meanings("dam_break")
    assert "(m)" in dam["dx"] and "(s)" in dam["t_end"] and "(m/s" in dam["c0"] and "(m/s^2)" in dam["g"]
    assert "(m)" in dam["width"] and "(m/s" in dam["shifting"]
    assert "(s)" in case_help.parameter_meanings("wave_flume")["period"]
    assert "(m/s^2)" in case_help.parameter_meanings("poiseuille")["F"]
    assert "(Pa)" in case_help.parameter_meanings("cylinder")["p_background"]


def test_a_docstring_line_defines_a_parameter(monkeypatch):
    """The form a case may use for any parameter: ``name (unit): meaning`` on its own line."""

    def case(dx: float = 0.1, gap: float = 0.2, frames: int = 10):
        """A case.

        Its gap (a word used in prose first) matters.

        gap (m): the width of the slot
        between the plates.
        """

    case.ranges = {"dx": parameters.positive, "gap": parameters.positive, "frames": parameters.frame_count}
    monkeypatch.setitem(catalogue.registry(), "slot", case)
    meanings = case_help.parameter_meanings("slot")
    assert meanings["gap"] == "(m) the width of the slot between the plates"
    assert "0: the initial frame only" in meanings["frames"]


def test_frames_help_agrees_with_frames_zero():
    """``frames`` showed ``[1, 100000]`` where ``--frames 0`` runs: both take 0 now (``--set frames=0`` too)."""
    text = " ".join(help_text("dam_break").split())
    assert "frames = 50 an integer in [0, 100000] frames written after the initial one (0: the initial frame only" in text
    assert "--frames FRAMES frames to write after the initial one (0 to 1e5; 0: the initial frame only" in text


def test_list_descriptions_end_on_whole_words(capsys):
    cli.list_cases()
    printed = capsys.readouterr().out
    entries = re.split(r"\n  (?=\S)", printed.split("\n", 1)[1].split("\nscene files")[0])
    assert len(entries) == len(CASES)
    for name, entry in zip(CASES, entries):
        text = " ".join(entry.split()[1:])
        module = inspect.getdoc(sys.modules[catalogue.find(name).__module__])
        whole = " ".join(module.split("\n\n")[0].split())
        assert whole.startswith(text.rstrip(".")) and text.endswith("."), (name, text)
        assert whole[len(text.rstrip(".")):][:1] in ("", "."), (name, text)  # a whole sentence, not a cut
    for line in printed.splitlines():
        assert len(line) <= 120


def test_a_long_description_wraps_at_words():
    words = "a description of a case that goes on well past the width of any terminal " * 3
    lines = case_help.list_entry("case", 10, words.strip(), columns=60).splitlines()
    assert len(lines) > 2 and all(len(line) <= 60 for line in lines)
    assert " ".join(" ".join(lines).split()[1:]) == " ".join(words.split())


def test_plot_is_dispatched_and_named(monkeypatch, capsys):
    seen = []
    plot = types.ModuleType("taisph.cli.plot")
    plot.main = lambda argv: seen.append(argv) or 7
    monkeypatch.setitem(sys.modules, "taisph.cli.plot", plot)
    assert cli.main(["plot", "out/dam_break", "--save", "x.png"]) == 7
    assert seen == [["out/dam_break", "--save", "x.png"]]
    assert cli.main(["no_such_command"]) == 2
    assert "commands: list, run, export, resume, sweep, plot" in capsys.readouterr().err
