"""The built-in cases and the shipped scene files: the registry, each case's parameters
(default and allowed range, declared in the case's file with
:func:`taisph.scene.parameters.checked`) and the one parser of ``NAME=VALUE`` settings.

Used by the command line (:mod:`taisph.cli`), sweeps (:mod:`taisph.sweeps`) and
validation runs.
"""

from __future__ import annotations

import importlib
import importlib.util
import inspect
import sys
from dataclasses import dataclass
from pathlib import Path

from .names import SOLVERS
from .parameters import ParameterError, Range

PACKAGE = __name__.split(".")[0]  # taisph


@dataclass(frozen=True)
class Parameter:
    """One parameter of a case: its name, default and allowed range."""

    name: str
    default: object
    range: Range


def load_cases():
    """The built-in cases as the package ``taisph.cases``, imported on first use.

    An installed taisph has them as a subpackage. A source checkout (``python -m
    taisph`` from the repository root) keeps them in ``cases/`` beside ``taisph/``.
    The cases are plug-ins that import taisph, so they are loaded by name, not by an
    import statement of this package.
    """
    name = f"{PACKAGE}.cases"
    if name in sys.modules:
        return sys.modules[name]
    try:
        return importlib.import_module(name)  # installed
    except ImportError:
        src = Path(__file__).resolve().parents[2] / "cases"
        spec = importlib.util.spec_from_file_location(name, src / "__init__.py", submodule_search_locations=[str(src)])
        if spec is None:
            raise ImportError(f"taisph's cases are neither installed nor in {src}") from None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        return module


def registry() -> dict:
    """The built-in cases, name -> function returning a :class:`taisph.Scene`."""
    return load_cases().CASES


def cases_folder() -> Path:
    """The folder of the built-in cases and the shipped scene files."""
    return Path(load_cases().__file__).resolve().parent


def scene_files() -> list:
    """The scene files shipped in cases/, sorted by name."""
    return sorted(cases_folder().glob("*.toml"))


def find_scene_file(name: str) -> Path:
    """`name` as given, or else the scene file of that name shipped in cases/."""
    path = Path(name)
    if not path.exists() and (cases_folder() / path.name).is_file():
        return cases_folder() / path.name
    return path


def find(name: str):
    """The case function called `name` (ParameterError listing the cases if none)."""
    cases = registry()
    if name not in cases:
        raise ParameterError(f"unknown case {name!r}; cases: {', '.join(cases)}")
    return cases[name]


def case_module(name: str):
    """The module of the built-in case `name` (``cases/<name>.py``: its function, and any
    plug-ins it defines, e.g. ``headline``, :mod:`taisph.run.results`), or None if there is
    no such case."""
    func = registry().get(name)
    return None if func is None else sys.modules.get(func.__module__)


def parameters(case: str) -> dict[str, Parameter]:
    """The parameters of case `case`, in signature order."""
    func = find(case)
    return {name: Parameter(name, p.default, func.ranges[name])
            for name, p in inspect.signature(func).parameters.items()}


def parse_setting(case: str, item: str) -> tuple[str, object]:
    """``NAME=VALUE`` from ``--set`` as (name, value), the value parsed by the
    parameter's range (a number, a word, true/false, none, or a comma-separated
    tuple). The range itself is checked when the case is called."""
    params = parameters(case)
    key, sep, text = item.partition("=")
    key = key.strip().replace("-", "_")
    if not sep:
        raise ParameterError(f"--set {item}: expected NAME=VALUE, e.g. --set {next(iter(params))}=...")
    if key not in params:
        raise ParameterError(f"--set {item}: {case} has no parameter {key!r}; its parameters: {', '.join(params)}")
    try:
        return key, params[key].range.parse(text.strip())
    except ValueError as err:
        raise ParameterError(f"--set {item}: {key} must be {params[key].range.describe()}; {err}") from None


def solver_setting(settings, solver=None):
    """(the other settings, the solver) from ``--set`` items and ``--solver``: every
    case takes ``--set solver=NAME`` (a setting of the scene, not a case parameter);
    the last one given wins, ``--solver`` over ``--set``."""
    rest, from_set = [], None
    for item in settings:
        key, sep, text = item.partition("=")
        if sep and key.strip().replace("-", "_") == "solver":
            from_set = text.strip().strip("'\"")
            if from_set not in SOLVERS:
                raise ParameterError(f"--set {item}: solver must be one of {', '.join(SOLVERS)}")
        else:
            rest.append(item)
    return rest, solver if solver is not None else from_set


def case_arguments(case: str, settings=(), **options) -> dict:
    """Keyword arguments for case `case`: the options given (e.g. dx, kernel; None
    means not given), then each ``--set NAME=VALUE`` of `settings`."""
    params = parameters(case)
    kwargs = {}
    for key, value in options.items():
        if value is not None:
            if key not in params:
                raise ParameterError(f"case {case} has no parameter {key!r}; its parameters: {', '.join(params)}")
            kwargs[key] = value
    for item in settings:
        key, value = parse_setting(case, item)
        kwargs[key] = value
    return kwargs

