"""What ``python -m taisph CASE --help`` says of a case (:func:`taisph.cli.case.build_parser`):
its parameters with their defaults, ranges and meanings, taken from the case's docstring
(:func:`parameter_meanings`), and examples of that case's own (:func:`case_examples`);
the one-line entries of ``python -m taisph list`` (:func:`list_entry`)."""

from __future__ import annotations

import inspect
import re
import textwrap

from ..scene import catalogue, parameters

# what a range says of the parameter that has it, for CASE --help: the ranges the cases share
# (taisph.scene.parameters), so a case's parameter of that range means this wherever it appears
RANGE_MEANINGS = (
    (parameters.viscosity_alpha, "Monaghan's artificial viscosity alpha (0: none)"),
    (parameters.speed_of_sound, "sound speed (m/s; None: the case's choice)"),
    (parameters.smoothing_factor, "smoothing length over particle spacing, h / dx"),
    (parameters.gravity_magnitude, "gravity's magnitude g (m/s^2)"),
    (parameters.diffusion_delta, "density diffusion coefficient delta of delta-SPH (0 or None: none)"),
    (parameters.xsph_epsilon, "XSPH epsilon: a fraction of the neighbours' mean velocity difference (0 or None: none)"),
    (parameters.courant_number, "Courant number C of the adaptive step dt = C h / max(c + |v|) (None: the case's)"),
    (parameters.reference_density, "reference density rho0 (kg/m^3)"),
    (parameters.tait_exponent, "Tait exponent gamma"),
    (parameters.end_time, "simulated end time (s)"),
    (parameters.frame_count, "frames written after the initial one (0: the initial frame only)"),
    (parameters.known_kernel, "smoothing kernel"),
    (parameters.known_integrator, "time integrator"),
    (parameters.known_solver, "solver: wcsph (weakly compressible) or dfsph (divergence-free SPH)"),
    (parameters.known_formulation, "the continuity and momentum equations' formulation"),
)
UNITS = r"(?:m\^2/s|m/s\^2|m/s|kg/m\^3|kg/m\^2|1/s|N/m|Pa|kg|rad|deg|m|s|N|J|K)"
# a docstring line that defines a parameter: "name: ...", "name (unit): ...", "- `name` (unit): ..."
DEFINITION_LINE = re.compile(r"^\s*(?:-\s+)?`{0,2}[A-Za-z_]\w*`{0,2}(?:\s*\([^()]*\))?:\s")
MEANING_WIDTH = 110  # characters of a docstring's clause shown for a parameter
NOT_SAID = " (the case's description does not say more)"


def describe_parameters(case: str) -> str:
    """``CASE --help``'s list of the case's parameters: ``name = default  range``, then
    what the parameter is (:func:`parameter_meanings`), wrapped."""
    params = catalogue.parameters(case).values()
    meanings = parameter_meanings(case)
    left = [f"  {p.name} = {p.default!r}" for p in params]
    width = max(len(s) for s in left) + 2
    lines = []
    for text, p in zip(left, params):
        lines.append(f"{text:<{width}}{p.range.describe()}")
        lines += textwrap.wrap(meanings[p.name], width=100, initial_indent=" " * 6, subsequent_indent=" " * 6,
                               break_long_words=False, break_on_hyphens=False)
    return "\n".join(lines)


def parameter_meanings(case: str, seen=()) -> dict:
    """What each of the case's parameters is, in words and with its unit, from the case's
    docstring: a line or sentence defining it (``name (unit): ...``, ``name: ...``), else,
    for a parameter of a range the cases share (a sound speed, a viscosity alpha...),
    :data:`RANGE_MEANINGS`, else the clause that first names it (with the unit beside
    it), else what a case the docstring refers to (``dam_break``) says of it; ``dx`` is the
    particle spacing; else its name in words."""
    func = catalogue.find(case)
    doc = inspect.getdoc(func) or ""
    paragraphs = _paragraphs(doc)
    others = [name for name in re.findall(r"``(\w+)``", doc) if name in catalogue.registry() and name != case
              and name not in seen]
    out = {}
    for name, p in catalogue.parameters(case).items():
        inner = getattr(p.range, "inner", p.range)  # optional(x): x's meaning
        meaning = next((text for rng, text in RANGE_MEANINGS if rng is inner), None)
        if name == "dx":
            meaning = "particle spacing (m): sets the resolution"
        meaning = _definition(name, paragraphs) or meaning or _mention(name, paragraphs)
        for other in others if meaning is None else ():
            said = parameter_meanings(other, (*seen, case)).get(name, "")
            if not said.endswith(NOT_SAID):
                meaning = f"as in {other}: {said}"
                break
        out[name] = meaning or f"{name.replace('_', ' ')}{NOT_SAID}"
    return out


def _paragraphs(doc: str) -> list:
    """A docstring's paragraphs, each on one line; a line that defines a parameter
    (:data:`DEFINITION_LINE`) after the end of a sentence starts a paragraph of its own."""
    out, lines = [], []
    for line in doc.splitlines() + [""]:
        starts = DEFINITION_LINE.match(line) and lines and lines[-1].rstrip().endswith((".", ":", ";"))
        if (not line.strip() or starts) and lines:
            out.append(" ".join(" ".join(lines).split()))
            lines = []
        if line.strip():
            lines.append(line)
    return out


def _shorten(text: str, limit: int = MEANING_WIDTH) -> str:
    """`text` up to `limit` characters, cut after a whole word with "..." if longer."""
    text = text.strip().rstrip(",:")
    if len(text) <= limit:
        return text
    return text[:limit].rsplit(" ", 1)[0].rstrip(",;:") + " ..."


def _clause(text: str, start: int = 0, stops: str = ".;") -> str:
    """`text` from `start` to the end of its clause ('. ' or '; ' outside brackets; `stops`)."""
    depth = 0
    for i in range(start, len(text)):
        if text[i] in "([":
            depth += 1
        elif text[i] in ")]":
            depth = max(0, depth - 1)
        elif text[i] in stops and depth == 0 and (i + 1 == len(text) or text[i + 1] == " "):
            return text[start:i]
    return text[start:]


def _definition(name: str, paragraphs) -> str | None:
    """The clause of the docstring that defines `name`: at the start of a paragraph, sentence
    or clause, ``name: ...``, ``name (unit): ...``, ``name = "value": ...``."""
    pattern = re.compile(r'(?:^|(?<=[.;:]\s))(?:-\s+)?`{0,2}' + re.escape(name) + r'`{0,2}(\s*=\s*"[^"]*")?'
                         r'(?:\s*\(([^()]*)\))?\s*:\s+')
    for text in paragraphs:
        found = pattern.search(text)
        if found:
            value, bracket = found.group(1), found.group(2)
            lead = f"{value.split('=', 1)[1].strip()}: " if value else ""
            if bracket:
                lead += f"({bracket}) "
            return _shorten(lead + _clause(text, found.end()))
    return None


def _mention(name: str, paragraphs) -> str | None:
    """Words of the clause that first names `name` (in backquotes, or as a whole word that
    is not a common English one), around it, with a unit given beside it in brackets."""
    quoted = re.compile(r"`{1,2}" + re.escape(name) + r"`{1,2}")
    symbol = not name.isalpha() or len(name) <= 2 or name.isupper()  # p_in, L, mu, R: not an English word
    # a word (gamma, beta) where it stands for the parameter: a symbol anywhere, else before "="
    word = re.compile(r"(?<![\w.`])" + re.escape(name) + (r"(?![\w`])" if symbol else r"(?=\s*=)"))
    for pattern in (quoted, word):
        for text in paragraphs:
            found = pattern.search(text)
            if not found:
                continue
            begin = max(text.rfind(". ", 0, found.start()), text.rfind("; ", 0, found.start()))
            begin = begin + 2 if begin >= 0 else 0
            clause = _clause(text, begin)
            if found.start() - begin > MEANING_WIDTH // 2:  # a long clause: from the words before the name
                cut = text.rfind(" ", begin, found.start() - MEANING_WIDTH // 3)
                clause, begin = "... " + text[cut + 1:begin + len(clause)], cut + 1
            unit = re.match(r"\s*\((" + UNITS + r")\b", text[found.end():])
            shown = _shorten(clause)
            if unit and f"({unit.group(1)}" not in shown:
                shown += f" ({name}: {unit.group(1)})"
            return shown
    return None


def first_sentence(doc: str) -> str:
    """The first sentence of a docstring's first paragraph, whole, on one line (for ``list``)."""
    paragraph = " ".join((doc or "").strip().split("\n\n")[0].split())
    sentence = _clause(paragraph, stops=".")
    return sentence.rstrip(".") + "." if sentence else ""


def list_entry(name: str, width: int, text: str, columns: int | None = None) -> str:
    """``  name  text`` for ``list``, `text` wrapped at whole words under itself to fit
    the terminal (`columns`; default its width, 100 where there is none)."""
    import shutil

    columns = columns or shutil.get_terminal_size((100, 24)).columns
    indent = " " * (width + 4)
    return textwrap.fill(text, width=max(columns, width + 40), initial_indent=f"  {name:<{width}}  ",
                         subsequent_indent=indent, break_long_words=False, break_on_hyphens=False)


def case_examples(case: str, scene) -> str:
    """``CASE --help``'s examples, for this case: its defaults, a shorter run, a coarser
    one (if the case builds at twice its dx), a checkpointed run and its resume."""
    short = ""
    if scene is not None:
        short = f" --t-end {scene.t_end / 2:g} --frames {max(1, scene.frames // 2)}"
    lines = [(f"python -m taisph {case}", f"the defaults; frames in out/{case}"),
             (f"python -m taisph {case}{short} --out run1", "")]
    coarse = _coarser(case, scene)
    if coarse:
        lines.append((f"python -m taisph {case} {coarse}", "coarser: quicker, less accurate"))
    lines += [(f"python -m taisph {case} > log.txt 2>&1", "a log: a progress line every 10 s"),
              (f"python -m taisph {case} --checkpoint-every 5 --out run2", "Ctrl-C, then:"),
              ("python -m taisph resume run2/checkpoint", "")]
    width = max(len(command) for command, _ in lines) + 2
    lines = [f"  {command:<{width}}# {note}" if note else f"  {command}" for command, note in lines]
    lines.append(f"Open OUT/{case}.pvd in ParaView (File > Open, Apply) to see the time series;\n"
                 "python -m taisph OUT says how OUT was made (OUT/run.json).")
    return "examples:\n" + "\n".join(lines)


def _coarser(case: str, scene) -> str | None:
    """``--dx DX`` at twice the case's default, if the case builds there (None if not)."""
    if scene is None or not scene.dx:
        return None
    dx = float(f"{2 * scene.dx:.3g}")
    try:
        catalogue.find(case)(dx=dx)
    except Exception:  # noqa: BLE001 -- a case that does not build there gets no such example
        return None
    return f"--dx {dx:g}"


