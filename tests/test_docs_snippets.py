"""Every Python and shell snippet of README.md and docs/*.md runs, as written, and where the
page quotes what it prints, the output is compared.

Rules (one test per fenced block, named ``FILE:LINE``, LINE the block's opening fence):

- A block's fence names its language; a block without one fails (``untagged``), as does a
  language this test does not know.
- ```python: written to a file and run with ``python`` in a fresh copy of the repository
  (its tracked and untracked, not ignored, files), so ``out/...`` lands in the copy,
  ``cases/`` and ``tools/`` are there and nothing is written to the checkout. The
  block's stdout is compared with the next block when that block is tagged
  ``<!-- output -->``.
- ```bash / ```sh / ```shell: run with ``bash -e`` in such a copy; a non-zero exit fails.
- ```console, or ```text with ``$ `` prompts: a session. Each ``$ COMMAND`` (``\\`` at a
  line's end continues it) is run with bash in such a copy, stdout and stderr together,
  and compared with the lines under it (below).
- Every other block (```text without ``$ ``, ```toml, ```csv, ...) is data and is not run;
  ``<!-- file: NAME -->`` before one writes it as NAME into the copy of every runnable
  block of the same page, so a session can run a scene file the page shows.
- An HTML comment on the lines just before a fence holds directives, ``;``-separated:
  ``slow: WHY`` (run only by ``pytest -m slow``: full runs of minutes, installs, sweeps),
  ``not run: WHY`` (skipped with WHY: a placeholder path, a peer code's environment, CI's
  own command), ``output`` (this block is the output of the block above),
  ``tolerance: rel R[, abs A]`` (numbers of the compared output), ``file: NAME``,
  ``mask: REGEX`` (the regex's groups are masked, as the timings below are), ``order: any``
  (lines that come as parallel runs finish: compared sorted). An unknown directive fails.

Comparing output: lines are compared in order (runs of blanks as one); a line ``...``
stands for any number of lines; Taichi's banner (``[Taichi] ...``) and progress lines (a
bar, or a plain line with the time left) are not output, on the page or in the run. The
words must be equal and the numbers equal within the tolerance (default rel 1e-6: as
printed); figures that vary with the machine and the load (wall time, ``ready in``,
particle-steps/s, steps/s, ns per step, elapsed time, a worker's host:pid, a sweep table's
timing columns) are masked on both sides. Paths inside the copy are printed relative to it.

The printed numbers compared here are regression fingerprints of the docs' output (that a
page still shows what its code prints), not validation: no comparison here claims agreement
with an experiment or an exact solution; those bars are in the tests of each case.

The fast part (every block not ``slow``) runs in about two minutes on two cores.
"""

import math
import os
import re
import shutil
import subprocess
import sys
import textwrap
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
FENCE = re.compile(r"^\s*```(\S*)\s*$")   # indented too (in a list item)
PYTHON, SHELL, SESSION, DATA = "python", "shell", "session", "data"
KINDS = {"python": PYTHON, "bash": SHELL, "sh": SHELL, "shell": SHELL, "console": SESSION}
DATA_LANGUAGES = {"text", "toml", "csv", "json", "ini", "yaml", "markdown", "md", "diff"}
DIRECTIVES = {"slow", "not run", "output", "tolerance", "file", "mask", "order"}
TIMEOUT_FAST, TIMEOUT_SLOW = 300, 7200
TIMING_MASKS = [
    r"ready in ([\d.]+) s",
    r"in ([\d.]+) s wall",
    r"\(([\d.]+) M fluid particle-steps/s\)",
    r"([\d.]+) (?:M )?(?:fluid )?(?:particle-)?steps/s",
    r"([\d.]+) ns per",
    r"\(([\d.]+) M/s\)",
    r"(\d+:\d\d:\d\d)",
    r"\b[\w.-]+:(\d+) \|",          # a sweep table's worker host:pid
    r"(?:ok|failed) \(\d+ steps, ([\d.]+) s",   # a sweep's progress line: the run's wall time
    r"the last state that passed the guards is from step (\d+), t = ([\d.e-]+) s",   # batches sized by wall time
]
TIMING_COLUMNS = {"wall s", "particle-steps/s", "wall s / sim s", "compile s", "worker"}
NOT_OUTPUT = re.compile(r"^\[Taichi\] "                                                    # Taichi's banner
                        r"|^\[[DIWE] \d\d/\d\d/\d\d \d\d:\d\d:\d\d\.\d+ \d+\] "           # Taichi's log
                        r"|: t = [-+\d.e]+ / [-+\d.e]+ s \([\d.]+ %\), \d+ steps, .* elapsed, "  # a progress line
                        r"|━")                                                                # a progress bar


@dataclass
class Block:
    page: Path
    line: int              # 1-based line of the opening fence
    language: str
    text: str
    directives: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}"

    @property
    def kind(self) -> str | None:
        if self.language in KINDS:
            return KINDS[self.language]
        if self.language == "text" and any(line.startswith("$ ") for line in self.text.splitlines()):
            return SESSION
        if self.language in DATA_LANGUAGES:
            return DATA
        return None


def parse_directives(lines: list[str], fence: int) -> dict:
    """The directives of the HTML comment that ends on the line before `fence` (0-based)."""
    end = fence - 1
    if end < 0 or not lines[end].rstrip().endswith("-->"):
        return {}
    start = end
    while not lines[start].lstrip().startswith("<!--"):
        start -= 1
        if start < 0 or lines[start].strip().startswith("```"):
            return {}
    comment = " ".join(line.strip() for line in lines[start:end + 1])
    body = comment.strip().removeprefix("<!--").removesuffix("-->").strip()
    directives = {}
    for item in filter(None, (part.strip() for part in body.split(";"))):
        key, _, value = item.partition(":")
        directives[key.strip()] = value.strip()
    return directives


@lru_cache(maxsize=None)
def blocks_of(page: Path) -> tuple:
    lines = page.read_text(encoding="utf-8").splitlines()
    blocks, i = [], 0
    while i < len(lines):
        match = FENCE.match(lines[i])
        if not match:
            i += 1
            continue
        end = i + 1
        while end < len(lines) and not lines[end].lstrip().startswith("```"):
            end += 1
        text = textwrap.dedent("\n".join(lines[i + 1:end]) + "\n")
        blocks.append(Block(page, i + 1, match.group(1), text, parse_directives(lines, i)))
        i = end + 1
    return tuple(blocks)


def all_blocks():
    return [b for page in PAGES for b in blocks_of(page)]


def runnable(block: Block) -> bool:
    return block.kind in (PYTHON, SHELL, SESSION)


def params():
    out = []
    for block in all_blocks():
        if block.kind == DATA:
            continue   # not run: test_every_block_is_classified checks its directives
        marks = [pytest.mark.slow] if "slow" in block.directives else []
        out.append(pytest.param(block, id=block.name, marks=marks))
    return out


# ---- the copy of the repository a block runs in

@lru_cache(maxsize=1)
def repository_files() -> tuple:
    listed = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT,
                            capture_output=True, check=True).stdout.decode().split("\0")
    return tuple(name for name in listed if name and (ROOT / name).is_file())


def workspace(tmp_path: Path, block: Block) -> Path:
    work = tmp_path / "repo"
    for name in repository_files():
        target = work / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, target)
    for other in blocks_of(block.page):
        if "file" in other.directives:
            (work / other.directives["file"]).write_text(other.text, encoding="utf-8")
    return work


def environment(tmp_path: Path, block: Block) -> dict:
    env = dict(os.environ, PYTHONUNBUFFERED="1", COLUMNS="200", TERM="dumb")
    env.pop("PYTHONPATH", None)
    for variable in ("PYTEST_XDIST_WORKER", "PYTEST_XDIST_TESTRUNUID", "PYTEST_CURRENT_TEST"):
        env.pop(variable, None)
    if "slow" in block.directives and "pip install" in block.text:
        env.update(overlay_venv(tmp_path / "venv"))
    return env


def overlay_venv(path: Path) -> dict:
    """A fresh virtual environment that also sees this one's packages (not taisph itself,
    whose editable install is a .pth there): `pip install .` installs taisph into it and
    finds its dependencies installed."""
    subprocess.run([sys.executable, "-m", "venv", str(path)], check=True)
    site = next(path.glob("lib/python*/site-packages"))
    here = [p for p in sys.path if p.endswith("site-packages") and Path(p).is_dir()]
    (site / "_taisph_docs_parent.pth").write_text("\n".join(here) + "\n")
    return {"VIRTUAL_ENV": str(path), "PATH": f"{path / 'bin'}{os.pathsep}{os.environ['PATH']}"}


def run(command: list[str], work: Path, env: dict, timeout: int) -> subprocess.CompletedProcess:
    return subprocess.run(command, cwd=work, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=timeout)


# ---- comparing output

NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


def tolerance(block: Block) -> tuple[float, float]:
    rel, absolute = 1e-6, 0.0
    for part in block.directives.get("tolerance", "").split(","):
        words = part.split()
        if len(words) == 2 and words[0] == "rel":
            rel = float(words[1])
        elif len(words) == 2 and words[0] == "abs":
            absolute = float(words[1])
        elif words:
            raise ValueError(f"{block.name}: tolerance: expected 'rel R' or 'abs A', got {part!r}")
    return rel, absolute


def mask(line: str, patterns: list[str], columns: set[int]) -> str:
    for pattern in patterns:
        for match in reversed(list(re.finditer(pattern, line))):
            for g in range(len(match.groups()), 0, -1):
                if match.group(g) is not None:
                    line = line[:match.start(g)] + "#" + line[match.end(g):]
    if columns and line.startswith("|"):
        cells = line.split("|")
        line = "|".join("#" if i - 1 in columns else c for i, c in enumerate(cells))
    return line


def table_columns(line: str) -> set[int] | None:
    """The timing columns of a table header line, or None if `line` is not one."""
    if not line.startswith("|") or line.startswith("|--") or line.startswith("|---"):
        return None
    names = [c.strip() for c in line.strip().strip("|").split("|")]
    if not any(n in TIMING_COLUMNS for n in names):
        return None
    return {i for i, n in enumerate(names) if n in TIMING_COLUMNS}


def masked_lines(lines: list[str], patterns: list[str]) -> list[str]:
    out, columns = [], set()
    for line in lines:
        header = table_columns(line)
        if header is not None:
            columns = header
        elif not line.startswith("|"):
            columns = set()
        out.append(mask(line, patterns, columns))
    return out


def same_line(expected: str, actual: str, rel: float, absolute: float) -> bool:
    e_words, a_words = NUMBER.split(expected), NUMBER.split(actual)
    if [" ".join(w.split()) for w in e_words] != [" ".join(w.split()) for w in a_words]:
        return False
    for e, a in zip(NUMBER.findall(expected), NUMBER.findall(actual)):
        x, y = float(e), float(a)
        if not math.isclose(x, y, rel_tol=rel, abs_tol=absolute):
            return False
    return True


def output_lines(text: str, work: Path) -> list[str]:
    text = text.replace(str(work) + "/", "").replace(str(work), ".")
    return [line.rstrip() for line in text.splitlines() if line.strip() and not NOT_OUTPUT.search(line)]


def match(expected: list[str], actual: list[str], rel: float, absolute: float) -> bool:
    """`expected` (``...`` lines matching any run of lines) against `actual`, in order."""
    if not expected:
        return not actual
    if expected[0] == "...":
        return any(match(expected[1:], actual[k:], rel, absolute) for k in range(len(actual) + 1))
    return bool(actual) and same_line(expected[0], actual[0], rel, absolute) and \
        match(expected[1:], actual[1:], rel, absolute)


def match_any_order(expected: list[str], actual: list[str], rel: float, absolute: float) -> bool:
    """``order: any``: each line of `expected` matches a line of `actual` of its own, in any
    order; `actual` may hold other lines only where `expected` has a ``...`` line."""
    left = list(actual)
    for line in (e for e in expected if e != "..."):
        found = next((k for k, a in enumerate(left) if same_line(line, a, rel, absolute)), None)
        if found is None:
            return False
        del left[found]
    return not left or "..." in expected


def compare(block: Block, expected_text: str, actual_text: str, work: Path, what: str):
    patterns = TIMING_MASKS + ([block.directives["mask"]] if "mask" in block.directives else [])
    expected = [line.rstrip() for line in expected_text.splitlines() if line.strip() and not NOT_OUTPUT.search(line)]
    actual = output_lines(actual_text, work)
    rel, absolute = tolerance(block)
    expected, actual = masked_lines(expected, patterns), masked_lines(actual, patterns)
    matcher = match_any_order if block.directives.get("order") == "any" else match
    if not matcher(expected, actual, rel, absolute):
        pytest.fail(f"{block.name}: {what} prints, masked and within rel {rel:g}, abs {absolute:g}, "
                    f"other than the page says.\n--- the page:\n" + "\n".join(expected) +
                    "\n--- the run:\n" + "\n".join(actual), pytrace=False)


def session(text: str) -> list[tuple[str, str]]:
    """(command, expected output) pairs of a ``$ `` session."""
    pairs, command, output, continued = [], None, [], False
    for line in text.splitlines():
        if continued:
            command += "\n" + line
            continued = line.endswith("\\")
        elif line.startswith("$ "):
            if command is not None:
                pairs.append((command, "\n".join(output)))
            command, output = line[2:], []
            continued = line.endswith("\\")
        elif command is not None:
            output.append(line)
    if command is not None:
        pairs.append((command, "\n".join(output)))
    return pairs


def next_block(block: Block) -> Block | None:
    blocks = blocks_of(block.page)
    i = blocks.index(block)
    return blocks[i + 1] if i + 1 < len(blocks) else None


# ---- the tests

def test_every_block_is_classified():
    """Every fenced block names a language this test knows, and its directives are known;
    an ``output`` block follows a runnable one, and a ``file`` block is data."""
    problems = []
    for block in all_blocks():
        if block.kind is None:
            problems.append(f"{block.name}: untagged or unknown language {block.language!r}: name it "
                            f"(python, bash, console, text, toml, ...)")
        unknown = set(block.directives) - DIRECTIVES
        if unknown:
            problems.append(f"{block.name}: unknown directive(s) {sorted(unknown)}")
        if "output" in block.directives:
            blocks = blocks_of(block.page)
            before = blocks[blocks.index(block) - 1] if blocks.index(block) else None
            if block.kind != DATA or before is None or before.kind not in (PYTHON, SHELL):
                problems.append(f"{block.name}: an output block must be data and follow a python or shell block")
        if "file" in block.directives and block.kind != DATA:
            problems.append(f"{block.name}: only a data block can be a file")
        if block.kind == DATA and {"slow", "not run"} & set(block.directives):
            problems.append(f"{block.name}: a data block is never run: 'slow' and 'not run' mean nothing there")
    assert not problems, "\n".join(problems)


def test_the_pages_have_snippets():
    kinds = [b.kind for b in all_blocks()]
    assert kinds.count(PYTHON) >= 5 and kinds.count(SHELL) >= 5 and kinds.count(SESSION) >= 3, kinds


@pytest.mark.parametrize("block", params())
def test_snippet(block: Block, tmp_path: Path):
    if "not run" in block.directives:
        pytest.skip(f"{block.name}: not run: {block.directives['not run']}")
    if block.kind is None:
        pytest.fail(f"{block.name}: a block with no language or an unknown one ({block.language!r}): "
                    f"tag it (python, bash, console, text, toml, ...)", pytrace=False)
    if not runnable(block):
        pytest.fail(f"{block.name}: directives {sorted(block.directives)} on a block that is not run")
    timeout = TIMEOUT_SLOW if "slow" in block.directives else TIMEOUT_FAST
    work = workspace(tmp_path, block)
    env = environment(tmp_path, block)
    if block.kind == PYTHON:
        script = work / "docs_snippet.py"
        script.write_text(block.text, encoding="utf-8")
        result = subprocess.run([sys.executable, script.name], cwd=work, env=env, capture_output=True,
                                text=True, timeout=timeout)
        assert result.returncode == 0, f"{block.name} failed:\n{result.stdout}\n{result.stderr}"
        following = next_block(block)
        if following is not None and "output" in following.directives:
            compare(following, following.text, result.stdout, work, "the block above")
    elif block.kind == SHELL:
        result = run(["bash", "-e", "-c", block.text], work, env, timeout)
        assert result.returncode == 0, f"{block.name} failed (exit {result.returncode}):\n{result.stdout}"
        following = next_block(block)
        if following is not None and "output" in following.directives:
            compare(following, following.text, result.stdout, work, "the block above")
    else:
        pairs = session(block.text)
        assert pairs, f"{block.name}: a session without commands"
        for command, expected in pairs:
            result = run(["bash", "-c", command], work, env, timeout)
            compare(block, expected, result.stdout, work, f"`{command}`")


def test_the_comparison_masks_timings_and_holds_figures():
    """The comparison itself: timings masked, figures held to the tolerance, ``...``."""
    work = Path("/nowhere")
    page = Block(ROOT / "README.md", 1, "text", "")
    line = "done: 5000 fluid, 3196 steps to t = 0.5 s in 15.41 s wall (1.04 M fluid particle-steps/s), mass 2000 kg"
    other = line.replace("15.41", "99.2").replace("1.04", "0.5")
    assert match(masked_lines([line], TIMING_MASKS), masked_lines([other], TIMING_MASKS), 1e-6, 0)
    moved = line.replace("3196", "3197")
    assert not match(masked_lines([line], TIMING_MASKS), masked_lines([moved], TIMING_MASKS), 1e-6, 0)
    assert match([line], [moved], 1e-3, 0)
    assert not match(["a 1", "b 2"], ["a 1"], 1e-6, 0)
    assert match(["a 1", "...", "c 3"], ["a 1", "b 2", "x", "c 3"], 1e-6, 0)
    assert output_lines("[Taichi] version 1.7.4\n/nowhere/out/x\n", work) == ["out/x"]
    table = ["| dx | status | wall s | worker |", "|---|---|---:|---|", "| 0.1 | ok | 0.47 | vm:11491 |"]
    run2 = table[:2] + ["| 0.1 | ok | 3.1 | host:7 |"]
    assert match(masked_lines(table, TIMING_MASKS), masked_lines(run2, TIMING_MASKS), 1e-6, 0)
    assert not match(masked_lines(table, TIMING_MASKS),
                     masked_lines(table[:2] + ["| 0.2 | ok | 0.47 | vm:11491 |"], TIMING_MASKS), 1e-6, 0)
    assert session("$ a \\\n  b\nout 1\n$ c\n") == [("a \\\n  b", "out 1"), ("c", "")]
    assert match_any_order(["b 2", "a 1"], ["a 1", "b 2"], 1e-6, 0)
    assert not match_any_order(["b 2", "a 1"], ["a 1", "b 2", "c 3"], 1e-6, 0)
    assert match_any_order(["...", "b 2", "a 1"], ["a 1", "c 3", "b 2"], 1e-6, 0)
    assert not match_any_order(["a 1", "a 1"], ["a 1", "b 2"], 1e-6, 0)
    assert page.kind == DATA
