"""What a sweep runs: the case, the names that may vary, and one task per combination.

Everything here runs in the process that starts the sweep, before any run, so that a
typo (an unknown case, an unknown parameter, a value that does not parse) is reported
at once and names what is allowed. Nothing here imports Dask.
"""

from __future__ import annotations

import inspect
import itertools
import math
import os
from dataclasses import dataclass, field
from typing import NamedTuple

from ..engine.timestep import SETTABLE, Controls
from ..scene.parameters import (ParameterError, Number, Range, at_least, between, courant_number, flag, integer, one_of,
                                optional, positive)


class Numbers(Range):
    """Any number of values of `inner`, comma-separated, in parentheses on a command
    line (e.g. a validation's sample ``times``: ``(0.1,0.5,1)``)."""

    def __init__(self, inner: Range):
        self.inner = inner

    def accepts(self, value) -> bool:
        try:
            items = tuple(value)
        except TypeError:
            return False
        return len(items) > 0 and all(self.inner.accepts(v) for v in items)

    def describe(self) -> str:
        return f"values {self.inner.describe()}, e.g. (0.1,0.5,1)"

    def parse(self, text: str):
        return tuple(self.inner.parse(w.strip()) for w in text.strip().strip("()").split(","))


def _default_text(value) -> str:
    """A control's default as the help shows it (None: the solver decides, e.g. max_speed)."""
    return "set by the solver" if value is None else f"{value:g}"


DEFAULT_PRECISION = "f64"  # a run's float precision unless a sweep sets or varies it

# Run settings: not case parameters but options of the simulation or of the runtime
# (the same as the plain command's options). name -> (allowed range, what it is)
SETTINGS = {
    "precision": (one_of("f32", "f64"), "float precision of the run"),
    "threads": (integer(at_least=1), "CPU threads of the run"),
    "dt": (optional(positive), "fixed time step (s); none: adaptive"),
    "courant": (courant_number, "Courant number of the adaptive step (default: the case's or scene file's own, "
                                f"else {Controls.courant:g})"),
    "neighbour_skin": (between(0, 2), "neighbour list skin (fraction of the support radius)"),
    "max_density_error": (at_least(0), "guard: stop when |rho/rho0 - 1| exceeds this (0: off)"),
    "deterministic": (flag, "serial cell sort: bit-for-bit reproducible runs"),
    "remove_escaped": (flag, "remove particles that leave the domain instead of stopping"),
    **{name: (rng, f"control {name} (default {_default_text(getattr(Controls, name))}; docs/dfsph.md)")
       for name, rng in SETTABLE.items()},  # dt_max, force_factor, DFSPH's solve controls, max_speed
}
# Keywords of the validation runs (taisph.validation.runs) and their ranges; every
# validation takes dt_factor (the case's step is multiplied by it).
VALIDATION_KEYWORDS = {"T_end": positive, "t_end": optional(positive), "samples": integer(at_least=1),
                       "times": Numbers(positive), "dt_factor": positive}
# Settings a validation run honours: it builds its simulation with the default controls.
VALIDATION_SETTINGS = ("precision", "threads")
# Validations that end at their reference's own times, not at the scene's t_end.
VALIDATION_END = {"dam_break": "T_end (dimensionless time of the reference, default 3.1)",
                  "poiseuille": "times (the reference's sample times, up to 1 s)",
                  "couette": "times (the reference's sample times, up to 1 s)"}


class SweepError(ValueError):
    """Bad input to a sweep, found before any run starts."""


class Name(NamedTuple):
    """A name a sweep may set or vary."""

    kind: str  # "case" (a parameter of the case), "setting" (a run setting), "validation" (its keyword)
    default: object
    range: Range  # what is allowed; parses text (taisph.scene.parameters)


def is_scene_file(case: str) -> bool:
    """Is the sweep's CASE a scene file (``*.toml``) rather than a built-in case?"""
    return str(case).endswith(".toml")


def resolve_case(case: str):
    """The scene factory of `case`: ``factory(**params) -> Scene``.

    The one place a sweep turns its CASE argument into scenes, in the starting
    process and in every worker: the command line's registry
    (:func:`taisph.scene.catalogue.find`), or for a scene file its factory
    (:func:`taisph.formats.scenefile.scene_factory`: dx, t_end, frames, integrator,
    kernel, h_factor, alpha, delta, xsph)."""
    if is_scene_file(case):
        from ..formats.scenefile import SceneFileError
        from ..formats.scenefile import scene_factory

        try:
            return scene_factory(case)
        except SceneFileError as err:
            raise SweepError(str(err)) from None
    from ..scene import catalogue

    try:
        return catalogue.find(case)
    except ParameterError as err:
        raise SweepError(str(err)) from None


def case_parameters(case: str) -> dict:
    """{name: Parameter (name, default, range)} of a built-in case or a scene file."""
    from ..scene import catalogue

    if not is_scene_file(case):
        return catalogue.parameters(case)
    factory = resolve_case(case)
    return {name: catalogue.Parameter(name, p.default, factory.ranges[name])
            for name, p in inspect.signature(factory).parameters.items()}


def has_reference(case: str) -> bool:
    from ..validation import VALIDATIONS

    return case in VALIDATIONS


def names(case: str, validate: bool) -> dict[str, Name]:
    """Every name a sweep of `case` may set or vary, with its kind, default and range:
    the case's parameters as declared in its file (:func:`taisph.scene.catalogue.parameters`),
    the run settings and, for validation runs, the validation's keywords."""
    allowed = {name: Name("case", p.default, p.range) for name, p in case_parameters(case).items()}
    allowed.update({name: Name("setting", None, rng) for name, (rng, _) in SETTINGS.items()})
    if validate:
        from ..validation import VALIDATIONS

        keywords = {name: p.default for name, p in inspect.signature(VALIDATIONS[case]).parameters.items()
                    if p.default is not inspect.Parameter.empty and name != "precision"}
        keywords["dt_factor"] = 1.0
        for name, default in keywords.items():
            allowed.setdefault(name, Name("validation", default, VALIDATION_KEYWORDS.get(name) or _range_of(default)))
    return allowed


def _range_of(default) -> Range:
    """A range for a validation keyword not in :data:`VALIDATION_KEYWORDS`, from its default."""
    if isinstance(default, bool):
        return flag
    if isinstance(default, tuple):
        return Numbers(Number())
    return optional(Number(integer=isinstance(default, int)))


def parse(case: str, name: str, value, allowed: dict[str, Name]):
    """`value` of `name` as the run needs it: text is parsed by the name's range (as
    ``--set`` parses it: :meth:`taisph.scene.parameters.Range.parse`), and every value must be
    in that range."""
    if name not in allowed:
        groups = {"case": "case parameters", "setting": "run settings", "validation": "validation keywords"}
        listed = "; ".join(f"{title}: {', '.join(n for n, a in allowed.items() if a.kind == kind)}"
                           for kind, title in groups.items() if any(a.kind == kind for a in allowed.values()))
        raise SweepError(f"{case} has no parameter {name!r}; allowed are {listed}")
    rng = allowed[name].range
    if isinstance(value, str):
        try:
            value = rng.parse(value.strip())
        except ValueError as err:
            raise SweepError(f"{name}: cannot read {value!r} ({err}); {name} must be {rng.describe()}") from None
    try:
        rng.check(name, value, case)
    except ParameterError as err:
        raise SweepError(str(err)) from None
    return value


def split_values(text: str) -> list[str]:
    """``"0.1,0.05"`` -> ["0.1", "0.05"]; commas inside parentheses stay (tuples)."""
    values, depth, current = [], 0, ""
    for char in text:
        depth += (char == "(") - (char == ")")
        if char == "," and depth == 0:
            values.append(current)
            current = ""
        else:
            current += char
    values.append(current)
    return [v.strip() for v in values]


def parse_vary(items) -> dict:
    """``["dx=0.1,0.05", "kernel=spline,wendland"]`` -> {"dx": ["0.1", "0.05"], ...}."""
    vary = {}
    for item in items:
        name, sep, text = item.partition("=")
        name = name.strip().replace("-", "_")
        if not sep or not name or not text.strip():
            raise SweepError(f"--vary expects NAME=v1,v2,..., got {item!r}")
        if name in vary:
            raise SweepError(f"--vary {name} is given twice; list all its values in one --vary")
        vary[name] = split_values(text)
    return vary


def value_text(value) -> str:
    """The text of a value in the table, in run names and in resume keys."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "none"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else str(value)
    if isinstance(value, tuple):
        return "(" + ",".join(value_text(v) for v in value) + ")"
    return str(value)


def run_name(combination: dict) -> str:
    """A combination's name: its table key and, with frames per run, its folder name."""
    if not combination:
        return "run"
    text = "_".join(f"{name}={value_text(value)}" for name, value in combination.items())
    return text.replace(os.sep, "-").replace(" ", "")


@dataclass
class Task:
    """One run of a sweep, as sent to a worker (picklable, no Taichi objects)."""

    case: str
    name: str
    params: dict  # case parameters, and validation keywords when `validate`
    settings: dict  # run settings (SETTINGS)
    validate: bool  # run the case's validation (error against its reference) or a plain run
    out: str | None = None  # folder for the run's frames, or None: no frames
    combination: dict = field(default_factory=dict)  # the varied values of this run
    tag: object = None  # the caller's own label, returned with the result


def _check_validation(case: str, given: set, frames_per_run: bool):
    """A validation run drives its own simulation: refuse options it would ignore."""
    ignored = sorted(n for n in given if n in SETTINGS and n not in VALIDATION_SETTINGS)
    if ignored:
        raise SweepError(f"{', '.join(ignored)}: not available when each run is {case}'s validation (it builds "
                         f"its simulation with the default controls; dt_factor scales its step); "
                         "add --no-validate (validate=False) for plain runs")
    if frames_per_run:
        raise SweepError(f"frames per run: {case}'s validation runs write no frames; "
                         "add --no-validate (validate=False) for plain runs with frames")
    if "t_end" in given and case in VALIDATION_END:
        raise SweepError(f"t_end: {case}'s validation runs to {VALIDATION_END[case]}, not to the scene's t_end; "
                         "set or vary that instead, or add --no-validate (validate=False) for plain runs to t_end")


def plan_tasks(case: str, vary: dict, fixed: dict, validate: bool | None = None, out: str | None = None,
         frames_per_run: bool = False) -> tuple[list[Task], bool]:
    """The tasks of the Cartesian product of `vary` ({name: values}), every run also
    given `fixed` ({name: value}); values may be text (parsed) or values. Returns
    (tasks, validate) where validate (default: the case has a reference) says whether
    each run is the case's validation run."""
    factory = resolve_case(case)
    if is_scene_file(case):  # workers may run elsewhere: the file's absolute path
        case = str(factory.path)
    if validate is None:
        validate = has_reference(case)
    elif validate and not has_reference(case):
        from ..validation import VALIDATIONS

        raise SweepError(f"{case} has no reference to validate against; cases with one: {', '.join(VALIDATIONS)}")
    allowed = names(case, validate)
    both = set(vary) & set(fixed)
    if both:
        raise SweepError(f"{', '.join(sorted(both))}: both varied and fixed; give each name once")
    parsed_vary = {}
    for name, values in vary.items():
        values = list(values) if isinstance(values, (list, tuple, range)) else [values]
        if not values:
            raise SweepError(f"{name}: no values to vary over")
        typed = [parse(case, name, v, allowed) for v in values]
        texts = [value_text(v) for v in typed]
        if len(set(texts)) != len(texts):
            raise SweepError(f"{name}: a value is given twice ({', '.join(texts)})")
        parsed_vary[name] = typed
    parsed_fixed = {name: parse(case, name, value, allowed) for name, value in fixed.items()}
    if validate:
        _check_validation(case, set(parsed_vary) | set(parsed_fixed), frames_per_run)
    tasks = []
    for values in itertools.product(*parsed_vary.values()):
        combination = dict(zip(parsed_vary, values))
        everything = {**parsed_fixed, **combination}
        settings = {k: v for k, v in everything.items() if allowed[k].kind == "setting"}
        settings.setdefault("precision", DEFAULT_PRECISION)
        if getattr(factory, "courant", None) is not None:  # a scene file's own Courant number
            settings.setdefault("courant", factory.courant)
        for key, value in getattr(factory, "controls", {}).items():  # and its other controls
            settings.setdefault(key, value)
        params = {k: v for k, v in everything.items() if allowed[k].kind != "setting"}
        name = run_name(combination)
        folder = os.path.join(out, name) if (out is not None and frames_per_run) else None
        tasks.append(Task(case, name, params, settings, validate, folder, combination))
    return tasks, validate
