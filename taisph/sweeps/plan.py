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

# Run settings: not case parameters but options of the simulation or of the runtime
# (the same as the plain command's options). name -> (parser, what it is)
SETTINGS = {
    "precision": ("f32 or f64", "float precision of the run"),
    "threads": ("int", "CPU threads of the run"),
    "dt": ("float or none", "fixed time step (s); none: adaptive"),
    "neighbour_skin": ("float", "neighbour list skin (fraction of the support radius)"),
    "max_density_error": ("float", "guard: stop when |rho/rho0 - 1| exceeds this (0: off)"),
    "deterministic": ("bool", "serial cell sort: bit-for-bit reproducible runs"),
    "remove_escaped": ("bool", "remove particles that leave the domain instead of stopping"),
}
# Settings a validation run honours: it builds its simulation with the default controls.
VALIDATION_SETTINGS = ("precision", "threads")
# Validations that end at their reference's own times, not at the scene's t_end.
VALIDATION_END = {"dam_break": "T_end (dimensionless time of the reference, default 3.1)",
                  "poiseuille": "times (the reference's sample times, up to 1 s)",
                  "couette": "times (the reference's sample times, up to 1 s)"}


class SweepError(ValueError):
    """Bad input to a sweep, found before any run starts."""


def resolve_case(case: str):
    """The scene factory of `case`: ``factory(**params) -> Scene``.

    The one place a sweep turns its CASE argument into scenes, in the starting
    process and in every worker (a scene file would be resolved here too)."""
    import taisph

    cases = taisph.cases.CASES
    if case not in cases:
        raise SweepError(f"unknown case {case!r}; the cases are: {', '.join(cases)}")
    return cases[case]


def has_reference(case: str) -> bool:
    from ..validation import VALIDATIONS

    return case in VALIDATIONS


def _defaults(func, skip=()) -> dict:
    return {name: p.default for name, p in inspect.signature(func).parameters.items()
            if p.default is not inspect.Parameter.empty and name not in skip}


def names(case: str, validate: bool) -> dict:
    """Every name a sweep of `case` may set or vary: name -> (kind, default), kind
    being "case" (a parameter of the case), "setting" (a run setting) or "validation"
    (a keyword of the case's validation run)."""
    allowed = {name: ("case", default) for name, default in _defaults(resolve_case(case)).items()}
    allowed.update({name: ("setting", None) for name in SETTINGS})
    if validate:
        from ..validation import VALIDATIONS

        for name, default in _defaults(VALIDATIONS[case], skip=("precision",)).items():
            allowed.setdefault(name, ("validation", default))
        allowed["dt_factor"] = ("validation", 1.0)  # every validation multiplies the case's step by it
    return allowed


def _parse_bool(text: str) -> bool:
    if text.lower() in ("1", "true", "yes", "on"):
        return True
    if text.lower() in ("0", "false", "no", "off"):
        return False
    raise ValueError(f"expected true or false, got {text!r}")


def _parse_setting(name: str, text: str):
    if name == "precision":
        if text not in ("f32", "f64"):
            raise ValueError(f"expected f32 or f64, got {text!r}")
        return text
    if name == "threads":
        value = int(text)
        if value < 1:
            raise ValueError(f"expected a positive integer, got {text!r}")
        return value
    if name in ("deterministic", "remove_escaped"):
        return _parse_bool(text)
    if name == "dt" and text.lower() in ("none", "adaptive"):
        return None
    return float(text)


def parse(case: str, name: str, value, allowed: dict):
    """`value` of `name` as the type the run needs (text is parsed; other values are kept)."""
    from ..cli.main import _parse_value

    if name not in allowed:
        groups = {"case": "case parameters", "setting": "run settings", "validation": "validation keywords"}
        listed = "; ".join(f"{title}: {', '.join(n for n, (k, _) in allowed.items() if k == kind)}"
                           for kind, title in groups.items() if any(k == kind for k, _ in allowed.values()))
        raise SweepError(f"{case} has no parameter {name!r}; allowed are {listed}")
    if not isinstance(value, str):
        return value
    kind, default = allowed[name]
    try:
        if kind == "setting":
            return _parse_setting(name, value.strip())
        if isinstance(default, str):
            return value.strip()
        return _parse_value(value.strip(), default)
    except ValueError as err:
        raise SweepError(f"{name}: cannot read {value!r} ({err}); expected {_expected(name, kind, default)}") from None


def _expected(name: str, kind: str, default) -> str:
    if kind == "setting":
        return SETTINGS[name][0]
    if isinstance(default, bool):
        what = "true or false"
    elif isinstance(default, int):
        what = "an integer"
    elif isinstance(default, tuple):
        what = "numbers in parentheses, e.g. (0,-9.81)"
    else:
        what = "a number"
    return f"{what} (default {default!r})"


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
    resolve_case(case)
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
        settings = {k: v for k, v in everything.items() if allowed[k][0] == "setting"}
        settings.setdefault("precision", "f64")
        params = {k: v for k, v in everything.items() if allowed[k][0] != "setting"}
        name = run_name(combination)
        folder = os.path.join(out, name) if (out is not None and frames_per_run) else None
        tasks.append(Task(case, name, params, settings, validate, folder, combination))
    return tasks, validate
