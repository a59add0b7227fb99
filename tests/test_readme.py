"""The README says what the code does: the option block it links to (docs/command_line.md)
lists every option of ``python -m taisph CASE``, and the defaults, counts and commands it
quotes are read here from the code (the parser, the default dam break scene, the time-step
controls, pyproject.toml), never from copies. No simulation runs: building the default
scenes is all (about a second). The README's snippets run in tests/test_docs_snippets.py."""

import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")
COMMAND_LINE = (ROOT / "docs" / "command_line.md").read_text(encoding="utf-8")
OPTION = re.compile(r"^\s+(--[a-z][a-z-]*)\b")


def section(title: str, text: str = README, name: str = "README.md") -> str:
    """The text of the ``## title`` section of `text`, up to the next ``## ``."""
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, re.M | re.S)
    assert match, f"{name} has no '## {title}' section"
    return match.group(1)


def first_block(text: str) -> str:
    """The first fenced code block of `text`."""
    match = re.search(r"^```\w*\n(.*?)^```", text, re.M | re.S)
    assert match, "no fenced code block"
    return match.group(1)


def option_block() -> str:
    """The command-line option block: the first code block of docs/command_line.md's
    '## Every option', which the README's '## Command line' links to."""
    assert "(docs/command_line.md)" in section("Command line"), "README.md no longer links the option block"
    return first_block(section("Every option", COMMAND_LINE, "docs/command_line.md"))


def option_entries() -> dict:
    """Each option of the block with its text: its line and the continuation lines
    indented below it, up to the next option, group heading or command."""
    entries, current = {}, None
    for line in option_block().splitlines():
        match = OPTION.match(line)
        if match:
            current = match.group(1)
            entries[current] = line
        elif current and line.startswith(" " * 10) and line.strip():
            entries[current] += "\n" + line
        else:
            current = None
    return entries


def case_parser():
    from taisph.cli.main import build_parser

    return build_parser("dam_break")


def parser_actions():
    return [a for a in case_parser()._actions if a.option_strings and "--help" not in a.option_strings]


def entry(option: str) -> str:
    entries = option_entries()
    assert option in entries, f"docs/command_line.md's option block has no line for {option}"
    return " ".join(entries[option].split())  # wrapped lines joined


@pytest.fixture(scope="module")
def dam_break():
    import taisph

    return taisph.cases.dam_break()


def test_every_option_of_a_case_is_in_the_readme_option_block():
    """Every option string of ``build_parser("dam_break")`` (-h/--help aside) appears in
    the option block (docs/command_line.md), and has a line of its own there."""
    block = option_block()
    strings = [s for a in parser_actions() for s in a.option_strings]
    assert len(strings) > 20  # the parser was really read
    missing = [s for s in strings if not re.search(rf"(?<![\w-]){re.escape(s)}(?![\w-])", block)]
    assert not missing, f"options missing from docs/command_line.md's option block: {missing}"
    no_line = [s for s in strings if s.startswith("--") and s not in option_entries()]
    assert not no_line, f"options without a line of their own in docs/command_line.md's option block: {no_line}"


def test_the_option_block_lists_no_option_the_parser_lacks():
    known = {s for a in parser_actions() for s in a.option_strings}
    assert set(option_entries()) <= known, set(option_entries()) - known


def test_parser_defaults_and_choices_are_quoted_as_they_are():
    """Options with a fixed default (--max-density-error 0.2, --max-out-of-range 0.001,
    --precision f64, --arch cpu) say 'default VALUE'; options with choices list them as
    the parser does."""
    checked = 0
    for action in parser_actions():
        option = action.option_strings[-1]
        if action.default not in (None, False, []):
            value = f"{action.default:g}" if isinstance(action.default, float) else str(action.default)
            assert re.search(rf"default:? {re.escape(value)}(?![\d.])", entry(option)), \
                f"docs/command_line.md: {option} should say 'default {value}': {entry(option)!r}"
            checked += 1
        if action.choices:
            assert "{" + ",".join(action.choices) + "}" in entry(option), (option, entry(option))
    assert checked >= 4


def test_max_density_and_out_of_range_defaults_match_the_simulation_controls():
    """The command line's defaults are the Simulation's (taisph.engine.timestep.Controls)."""
    from taisph.engine.timestep import Controls

    controls = Controls()
    assert f"default {controls.max_density_error:g}" in entry("--max-density-error")
    assert f"default {controls.max_out_of_range:g}" in entry("--max-out-of-range")


def test_case_dependent_defaults_are_the_dam_breaks(dam_break):
    """--dx, --t-end, --frames quote the dam break's defaults; --integrator and --kernel
    the one most built-in cases have (and the others, named); --neighbour-skin the Scene's."""
    import inspect

    import taisph

    assert f"dam_break {dam_break.dx:g})" in entry("--dx")
    assert f"dam_break {dam_break.t_end:g})" in entry("--t-end")
    assert f"dam_break {dam_break.frames})" in entry("--frames")
    for option, name in (("--integrator", "integrator"), ("--kernel", "kernel")):
        by_case = {case: inspect.signature(f).parameters[name].default for case, f in taisph.cases.CASES.items()}
        common = max(set(by_case.values()), key=list(by_case.values()).count)
        others = sorted(case for case, default in by_case.items() if default != common)
        quoted = f"({common} in every built-in case" + "".join(
            f"; {by_case[case]} in {case}" for case in others) + ")"
        assert quoted in entry(option), (quoted, entry(option))
    assert f"default {taisph.Scene.neighbour_skin:g}:" in entry("--neighbour-skin")


def test_the_courant_defaults_quoted_are_the_codes(dam_break):
    """--courant: the 2D and 3D dam breaks' own numbers, the engine's default and
    DFSPH's, as the step controls choose them; the known-limits text says the same."""
    import taisph
    from taisph.engine.dfsph.method import DFSPH_COURANT
    from taisph.engine.timestep import Controls, controls_for

    text = entry("--courant")
    assert controls_for(dam_break).courant == dam_break.courant
    assert f"dam_break {dam_break.courant:g} in 2D" in text
    assert f"dam_break_3d {taisph.cases.dam_break_3d().courant:g}" in text
    assert f"else {Controls().courant:g}" in text
    assert f"DFSPH: dt = C h / max |v|, default {DFSPH_COURANT:g}" in text
    dfsph = taisph.cases.dam_break()
    dfsph.solver = "dfsph"
    assert controls_for(dfsph).courant == DFSPH_COURANT
    quoted = re.findall(r"2D dam break's Courant number ([\d.]+)", README)
    assert quoted and all(float(c) == dam_break.courant for c in quoted), quoted


def test_the_pasted_run_is_what_the_default_dam_break_prints(dam_break):
    """The output block under 'What you get' starts with the scene's own description,
    line for line, and its numbers are the scene's."""
    block = first_block(section("What you get"))
    lines = block.splitlines()
    for line in dam_break.describe().splitlines():
        assert line in lines, f"README.md's run output lacks the line the code prints: {line!r}"
    assert f"adaptive dt (Courant {dam_break.courant:g};" in block
    assert f"done: {dam_break.n_fluid} fluid + {dam_break.n_wall} wall particles" in block


def test_the_default_runs_size_and_time_are_quoted_right(dam_break):
    match = re.search(r"runs (\d+) fluid particles for ([\d.]+) s of simulated time", README)
    assert match, "README.md no longer says how large the default run is"
    assert int(match.group(1)) == dam_break.n_fluid
    assert float(match.group(2)) == dam_break.t_end


def test_install_and_test_commands_and_python_version():
    """The two commands CI runs (.ci/run) are the README's, and the Python version is
    pyproject's."""
    assert "```bash\npip install . && python -m taisph dam_break\n```" in README
    assert "```bash\npip install \".[test]\" && pytest\n```" in README
    ci = (ROOT / ".ci" / "run").read_text()
    assert 'pip install ".[test]" && pytest' in ci
    pyproject = load_pyproject()
    version = pyproject["project"]["requires-python"].removeprefix(">=")
    assert f"Python ≥ {version}." in README


def load_pyproject() -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:
        import tomli as tomllib
    return tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_every_extra_dependency_has_its_reason_in_the_readme():
    """The project's rule: a dependency beyond taichi, numpy, meshio, pytest and Dask
    distributed is named, with its reason, in the README's Dependencies section."""
    allowed = {"taichi", "numpy", "meshio", "pytest", "distributed"}
    project = load_pyproject()["project"]
    requirements = project["dependencies"] + [r for extra in project["optional-dependencies"].values()
                                              for r in extra]
    names = {re.match(r"[A-Za-z0-9_.-]+", r).group(0).lower() for r in requirements}
    deps = section("Dependencies")
    missing = sorted(n for n in names - allowed if n not in deps.lower())
    assert not missing, f"dependencies without a reason in README.md: {missing}"


def test_every_docs_path_the_readme_names_exists():
    paths = set(re.findall(r"\]\((docs/[^)#\s]+)", README)) | set(re.findall(r"`(docs/[\w./-]+)`", README))
    assert "docs/dam_break.png" in paths
    assert not [p for p in sorted(paths) if not (ROOT / p).exists()]


def test_every_python_m_module_the_readme_names_exists():
    """``python -m package.module`` commands in the README name modules of this
    repository (the module's file exists; nothing is imported or run)."""
    modules = set(re.findall(r"python -m ([a-z_]+(?:\.[a-z_]+)+)", README))
    assert modules
    missing = [m for m in sorted(modules) if not (ROOT.joinpath(*m.split(".")).with_suffix(".py")).exists()]
    assert not missing, f"README.md names modules that do not exist: {missing}"
