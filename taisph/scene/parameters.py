"""Allowed ranges of parameters, declared once and checked on every call.

A case declares the range of each of its parameters next to its signature::

    @checked(dx=positive, alpha=at_least(0), c0=optional(positive), walls=one_of("lj", "dummy"),
             frames=integer(at_least=1), ...)
    def dam_break(dx=0.02, alpha=0.1, c0=None, walls="lj", frames=50, ...):

and every call, from Python or from the command line, is checked before anything is
built: ``dam_break(dx=-1)`` raises :class:`ParameterError` "dam_break: dx must be > 0,
got -1". The same declaration gives the command line its ``--set NAME=VALUE`` parsing
(:meth:`Range.parse`) and ``CASE --help`` its ranges (:meth:`Range.describe`); the
command line's options use the same ranges (:func:`taisph.cli.parser.ranged`).

A range checks one value. What depends on several parameters (the column must fit
in its tank, dx must leave particles in a block: :func:`lattice_count`) is checked in
the case's body, raising :class:`ParameterError` with the names of all involved.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import os

import numpy as np

from ..messages import InputError
from .names import FORMULATIONS, INTEGRATORS, KERNELS, SOLVERS


class ParameterError(InputError):
    """A parameter outside its allowed range, or a word that does not parse as one. The
    message names the case or option, the parameter, its value and what is allowed
    (an :class:`taisph.messages.InputError`: exit code 2 on the command line)."""


class Range:
    """The values one parameter may take."""

    def accepts(self, value) -> bool:
        raise NotImplementedError

    def describe(self) -> str:
        """What is allowed, to follow "must be" (e.g. ``> 0``, ``one of 'lj', 'dummy'``)."""
        raise NotImplementedError

    def parse(self, text: str):
        """The value a command-line word stands for (:class:`ParameterError`, a ValueError,
        saying what was expected)."""
        raise NotImplementedError

    def check(self, name: str, value, owner: str = "") -> None:
        """Raise :class:`ParameterError` unless `value` is allowed."""
        if not self.accepts(value):
            where = f"{owner}: " if owner else ""
            raise ParameterError(f"{where}{name} must be {self.describe()}, got {value!r}")

    def __str__(self) -> str:
        return self.describe()


def _number(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


class Number(Range):
    """A finite real number between optional bounds (``integer``: a whole number)."""

    def __init__(self, low=None, high=None, low_open=False, high_open=False, integer=False):
        self.low, self.high, self.low_open, self.high_open, self.integer = low, high, low_open, high_open, integer

    def accepts(self, value) -> bool:
        if not _number(value):
            return False
        try:  # an integer beyond the float range (Python's ints have no bound) is out of range
            if not math.isfinite(value):
                return False
        except OverflowError:
            return False
        if self.integer and not isinstance(value, numbers.Integral):
            return False
        if self.low is not None and (value <= self.low if self.low_open else value < self.low):
            return False
        if self.high is not None and (value >= self.high if self.high_open else value > self.high):
            return False
        return True

    def describe(self) -> str:
        kind = "an integer" if self.integer else ""
        low = None if self.low is None else f"{'>' if self.low_open else '>='} {self.low:g}"
        high = None if self.high is None else f"{'<' if self.high_open else '<='} {self.high:g}"
        if low and high:
            bounds = f"in {'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"
        else:
            bounds = low or high or ""
        if not bounds:
            return kind or "a finite number"
        return f"{kind} {bounds}".strip()

    def parse(self, text: str):
        try:
            return int(text) if self.integer else float(text)
        except ValueError:
            raise ParameterError(f"expected {'an integer' if self.integer else 'a number'}, got {text!r}") from None


def at_least(low) -> Number:
    return Number(low=low)


def greater_than(low) -> Number:
    return Number(low=low, low_open=True)


def between(low, high) -> Number:
    """low <= value <= high."""
    return Number(low=low, high=high)


def integer(at_least=None, at_most=None) -> Number:
    return Number(low=at_least, high=at_most, integer=True)


positive = greater_than(0)
finite = Number()
# h / dx: at 0.5 and below, the support of the cubic spline and of Wendland C2 (2h) no
# longer reaches the nearest neighbour; above 3 a particle has hundreds (2D) to
# thousands (3D) of neighbours.
smoothing_factor = Number(0.5, 3.0, low_open=True)
# dt = C h / c: the CFL condition asks for C below 1 (the gas cases are stable up to 0.5)
courant_number = Number(0, 1, low_open=True)
# The ranges of quantities cases, scene files and the command line share (one range each,
# so a value is refused in the same words wherever it is given):
# t_end (s): about a day of simulated time is millions of steps at any resolution the
# engine runs; beyond it, a mistyped exponent
end_time = Number(0, 1e5, low_open=True)
# frames written (each frame's time is kept in a list: 10^5 is a frame per 10 ms for 1000 s)
# frames written after the initial one: 0 writes the initial frame only (a case's frames=, --frames)
frame_count = output_frames = integer(at_least=0, at_most=100_000)
seed_frames = integer(at_least=1, at_most=100_000)  # the seed's `run` writes at least one
# Monaghan's alpha: the artificial viscosity h alpha c / (2 (d + 2)) keeps the explicit
# viscous limit of the step (0.125 h^2 / nu) above the CFL step (0.25 h / c) up to
# alpha = 4; 1 for shocks (Monaghan 1992), 0.01-0.1 for free-surface flows
viscosity_alpha = between(0, 2)
# delta-SPH's delta (a diffusivity delta h c0): 0.1 (Antuono et al. 2010); at 1 its
# explicit limit h / (2 d delta c0) is already about the CFL step 0.25 h / c0
diffusion_delta = between(0, 1)
# XSPH's epsilon: a fraction of the neighbours' mean velocity difference (0.5 Monaghan 1989)
xsph_epsilon = between(0, 1)
# gravity (m/s^2): up to 100 g (the sound speed 10 sqrt(2 g H) follows it)
gravity_magnitude = Number(0, 1000, low_open=True)
gravity_component = between(-1000, 1000)
# a material's reference density (kg/m^3; the densest liquid, mercury, is 13 500),
# sound speed (m/s; water's is 1480) and Tait exponent (water's 7)
reference_density = Number(0, 1e5, low_open=True)
speed_of_sound = Number(0, 1e5, low_open=True)
tait_exponent = Number(0, 20, low_open=True)
# a velocity component (m/s): the sound speed, 10 times the fastest flow, stays in range
velocity_component = between(-1e4, 1e4)
# a position component (m): 1000 km; beyond it, single-precision positions (7 digits)
# no longer resolve a metre, and the neighbour grid of any resolution is too large
position_component = between(-1e6, 1e6)
# a particle's mass (kg): a cube of the densest liquid (1e5 kg/m^3 at most) 100 m wide
particle_mass = Number(0, 1e11, low_open=True)
# a particle spacing (m) as a solver may take it: from a micrometre to a kilometre (the
# kernel's normalisation h^-(dim+2) stays within single precision)
particle_spacing = between(1e-6, 1e3)


# The ranges of the scene's runtime parameters (:meth:`taisph.Scene.set`, ``sim.set``): each
# term's parameters, by name (a vector's: each component's), the smoothing length and the
# materials' constants, the same ranges the command line and scene files apply to the same
# quantities. A term's parameter not listed here must be a finite number
# (tests/test_bad_input_more.py holds every term's parameters listed).
RUNTIME = {
    "alpha": viscosity_alpha, "beta": Number(low=0), "eta_factor": Number(0, 1, low_open=True),
    "delta": diffusion_delta, "xsph_eps": xsph_epsilon, "lattice_ratio": Number(0, 1e3, low_open=True),
    "riemann_eta": Number(0, 100), "shift_speed": Number(0, 1e4), "shift_dx": particle_spacing,
    "shift_cap": Number(0, 1), "damping_start": position_component, "damping_direction": position_component,
    "damping_rate": Number(0, 1e6), "drain_lo": position_component, "drain_hi": position_component,
    "relaxation_time": Number(0, 1e5, low_open=True), "contact_stiffness": Number(low=0),
    "contact_damping": Number(low=0), "contact_distance": Number(0, 1e3), "lj_strength": Number(low=0),
    "lj_cutoff": Number(0, 1e3, low_open=True), "alpha_u": Number(0, 10), "h_factor": smoothing_factor,
    "gravity": gravity_component, "nu": Number(0, 100),
    "smoothing_length": particle_spacing, "rho0": reference_density, "c0": speed_of_sound, "gamma": tait_exponent,
    "sigma": Number(0, 1e3), "viscosity": Number(0, 1e6), "background_pressure": Number(0, 1e9),
}


def check_runtime(name: str, value, owner: str = "") -> None:
    """Raise :class:`ParameterError` naming `name`, `value` and the allowed range unless
    `value` is allowed for the runtime parameter `name` (:data:`RUNTIME`; a number, or
    for a vector parameter every component)."""
    rng = RUNTIME.get(name, finite)
    try:
        scalar = np.ndim(value) == 0
    except ValueError:  # a ragged sequence
        scalar = False
    if scalar:
        rng.check(name, np.asarray(value).item() if isinstance(value, (np.generic, np.ndarray)) else value, owner)
        return
    try:
        items = [float(v) for v in np.asarray(value, float).ravel()]
    except (TypeError, ValueError):
        items = []
    if not items or not all(rng.accepts(v) for v in items):
        where = f"{owner}: " if owner else ""
        raise ParameterError(f"{where}{name} must have every component {rng.describe()}, got {value!r}")


class OneOf(Range):
    """One of a few values (compared with ==; on a command line, by their text)."""

    def __init__(self, *choices):
        self.choices = choices

    def accepts(self, value) -> bool:
        return any(value == c and (type(value) is type(c) or (_number(value) and _number(c)))
                   for c in self.choices)

    def describe(self) -> str:
        return "one of " + ", ".join(repr(c) for c in self.choices)

    def parse(self, text: str):
        for c in self.choices:
            if str(c) == text:
                return c
        raise ParameterError(f"expected one of {', '.join(str(c) for c in self.choices)}, got {text!r}")


def one_of(*choices) -> OneOf:
    return OneOf(*choices)


known_kernel = one_of(*KERNELS)
known_integrator = one_of(*INTEGRATORS)
known_solver = one_of(*SOLVERS)
known_formulation = one_of(*FORMULATIONS)


class Flag(Range):
    """True or False (on a command line: true/false, yes/no, on/off, 1/0)."""

    WORDS = {"true": True, "yes": True, "on": True, "1": True, "false": False, "no": False, "off": False, "0": False}

    def accepts(self, value) -> bool:
        return isinstance(value, bool)

    def describe(self) -> str:
        return "True or False"

    def parse(self, text: str):
        try:
            return self.WORDS[text.lower()]
        except KeyError:
            raise ParameterError(f"expected true or false, got {text!r}") from None


flag = Flag()


class Optional(Range):
    """None (the case then chooses, or leaves the effect out) or a value of `inner`."""

    def __init__(self, inner: Range):
        self.inner = inner

    def accepts(self, value) -> bool:
        return value is None or self.inner.accepts(value)

    def describe(self) -> str:
        return f"{self.inner.describe()} or None"

    def parse(self, text: str):
        return None if text.lower() == "none" else self.inner.parse(text)


def optional(inner: Range) -> Optional:
    return Optional(inner)


class Vector(Range):
    """A fixed number of components, each with its own range, e.g. a state (rho, u, p)."""

    def __init__(self, names, *components: Range):
        self.names, self.components = tuple(names), components

    def accepts(self, value) -> bool:
        try:
            items = tuple(value)
        except TypeError:
            return False
        return len(items) == len(self.components) and all(c.accepts(v) for c, v in zip(self.components, items))

    def describe(self) -> str:
        parts = ", ".join(f"{n} {c.describe()}" for n, c in zip(self.names, self.components))
        return f"({', '.join(self.names)}) with {parts}"

    def parse(self, text: str):
        words = text.strip().strip("()").split(",")
        if len(words) != len(self.components):
            raise ParameterError(f"expected {len(self.components)} comma-separated values "
                                 f"({','.join(self.names)}), got {text!r}")
        return tuple(c.parse(w.strip()) for c, w in zip(self.components, words))


def vector(names, *components: Range) -> Vector:
    return Vector(names, *components)


def checked(**ranges: Range):
    """Decorate a function whose every parameter has a declared range: each call is
    checked (defaults included) and raises :class:`ParameterError` naming the first
    parameter out of range. The ranges are kept as ``func.ranges`` (in signature order)
    for ``--help`` and ``--set``. A scene a built-in case (``cases/<name>.py``) returns
    records the case's name and every parameter's value (``scene.case``,
    ``scene.case_parameters``: what the case's headline results read,
    :mod:`taisph.run.results`). Declaring too few or too many parameters, or a default
    outside its own range, is a programming error (TypeError at import)."""

    def decorate(func):
        signature = inspect.signature(func)
        names = list(signature.parameters)
        missing = [n for n in names if n not in ranges]
        unknown = [n for n in ranges if n not in signature.parameters]
        if missing or unknown:
            raise TypeError(f"@checked on {func.__name__}: no range for {missing}; no parameter {unknown}")
        for name, p in signature.parameters.items():
            if p.default is not inspect.Parameter.empty and not ranges[name].accepts(p.default):
                raise TypeError(f"@checked on {func.__name__}: the default {name}={p.default!r} is not "
                                f"{ranges[name].describe()}")

        is_case = func.__module__.rpartition(".")[0].endswith("cases")  # a built-in case: cases/<name>.py

        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            try:
                bound = signature.bind(*args, **kwargs)
            except TypeError as err:
                raise ParameterError(f"{func.__name__}: {err}; its parameters are {', '.join(names)}") from None
            bound.apply_defaults()
            for name, value in bound.arguments.items():
                ranges[name].check(name, value, func.__name__)
            result = func(*bound.args, **bound.kwargs)
            if is_case and isinstance(getattr(result, "case", None), str):  # a Scene: the case that made it, how
                result.case, result.case_parameters = func.__name__, dict(bound.arguments)
            return result

        wrapper.ranges = {name: ranges[name] for name in names}
        return wrapper

    return decorate


# --- what several parameters decide together --------------------------------------------------
# A simulation holds at least this many bytes per particle (positions, velocities, rates
# and the sort's copies; 328 in 2D and 400 in 3D for the dam break, docs/performance.md):
# a resolution that needs more memory than the machine has is refused before building.
BYTES_PER_PARTICLE = 300


def _memory_bytes() -> float:
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, ValueError, OSError):  # not a POSIX system: no limit known
        return math.inf


def lattice_count(owner: str, what: str, spacing: float, *sides: tuple, spacing_name: str = "dx") -> int:
    """The number of particles a lattice of `spacing` puts in a block with these
    sides, each given as (the name a user knows it by, its length in m), e.g.
    ``lattice_count("dam_break", "the water column", dx, ("width", 1.0), ("height", 2.0))``.

    Raises :class:`ParameterError` naming the spacing (as `spacing_name`, e.g. "dx/2")
    and the sides if a side is shorter than the spacing (the block would get no
    particle along it), or if the particles would need more memory than the machine
    has (at least :data:`BYTES_PER_PARTICLE` each)."""
    name, shortest = min(sides, key=lambda side: side[1])
    listed = ", ".join(dict.fromkeys(f"{k} = {v:g} m" for k, v in sides))
    given = f"{spacing_name} = {spacing:g} m"
    if spacing > shortest * (1 + 1e-9):
        raise ParameterError(f"{owner}: {given} leaves {what} ({listed}) without particles along {name}: "
                             f"{spacing_name} must be at most {shortest:g} m")
    count = math.prod(max(1, round(v / spacing)) for _, v in sides)
    problem = memory_shortage(count)
    if problem:
        raise ParameterError(f"{owner}: {given} fills {what} ({listed}) with {count:.3g} particles, {problem}")
    return count


def memory_shortage(count: float, bytes_per_particle: float = BYTES_PER_PARTICLE) -> str:
    """'' if `count` particles fit in this machine's memory (at least
    `bytes_per_particle` each, by default :data:`BYTES_PER_PARTICLE`: a solver that
    stores more per particle, such as DFSPH's pair list, says so), else what is wrong,
    to follow "N particles, "."""
    need, have = count * bytes_per_particle, _memory_bytes()
    if need <= have:
        return ""
    return f"which need at least {need / 1e9:.3g} GB; this machine has {have / 1e9:.3g} GB: use a larger dx"

