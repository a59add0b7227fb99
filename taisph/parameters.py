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

from .engine.integrators import INTEGRATORS
from .engine.smoothing import KERNELS


class ParameterError(ValueError):
    """A parameter outside its allowed range. The message names the case or option,
    the parameter, its value and what is allowed."""


class Range:
    """The values one parameter may take."""

    def accepts(self, value) -> bool:
        raise NotImplementedError

    def describe(self) -> str:
        """What is allowed, to follow "must be" (e.g. ``> 0``, ``one of 'lj', 'dummy'``)."""
        raise NotImplementedError

    def parse(self, text: str):
        """The value a command-line word stands for (ValueError saying what was expected)."""
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
        if not _number(value) or not math.isfinite(value):
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
            raise ValueError(f"expected {'an integer' if self.integer else 'a number'}, got {text!r}") from None


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
        raise ValueError(f"expected one of {', '.join(str(c) for c in self.choices)}, got {text!r}")


def one_of(*choices) -> OneOf:
    return OneOf(*choices)


known_kernel = one_of(*KERNELS)
known_integrator = one_of(*INTEGRATORS)


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
            raise ValueError(f"expected true or false, got {text!r}") from None


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
            raise ValueError(f"expected {len(self.components)} comma-separated values "
                             f"({','.join(self.names)}), got {text!r}")
        return tuple(c.parse(w.strip()) for c, w in zip(self.components, words))


def vector(names, *components: Range) -> Vector:
    return Vector(names, *components)


def checked(**ranges: Range):
    """Decorate a function whose every parameter has a declared range: each call is
    checked (defaults included) and raises :class:`ParameterError` naming the first
    parameter out of range. The ranges are kept as ``func.ranges`` (in signature order)
    for ``--help`` and ``--set``. Declaring too few or too many parameters, or a
    default outside its own range, is a programming error (TypeError at import)."""

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

        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            try:
                bound = signature.bind(*args, **kwargs)
            except TypeError as err:
                raise ParameterError(f"{func.__name__}: {err}; its parameters are {', '.join(names)}") from None
            bound.apply_defaults()
            for name, value in bound.arguments.items():
                ranges[name].check(name, value, func.__name__)
            return func(*bound.args, **bound.kwargs)

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
    need, have = count * BYTES_PER_PARTICLE, _memory_bytes()
    if need > have:
        raise ParameterError(f"{owner}: {given} fills {what} ({listed}) with {count:.3g} particles, which need "
                             f"at least {need / 1e9:.3g} GB; this machine has {have / 1e9:.3g} GB: use a larger dx")
    return count

