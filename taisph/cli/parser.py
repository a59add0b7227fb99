"""The argument parser of every taisph command, and argparse types with ranges.

:class:`Parser` raises :class:`UsageError` instead of exiting, so each command prints
the message its way and returns exit code 2 (``--help`` still prints and exits 0).
:func:`ranged` turns a :class:`taisph.scene.parameters.Range` into an argparse type, so an
option out of range is refused with its name, value and range before anything is
built: ``argument --dx: must be > 0, got -1``.
"""

from __future__ import annotations

import argparse

from ..messages import InputError
from ..scene.parameters import (Range, at_least, between, courant_number, end_time, integer, output_frames, seed_frames,
                                positive)


class UsageError(InputError):
    """A command line that cannot be run: the message says what and what is allowed
    (an :class:`taisph.messages.InputError`: exit code 2)."""


class Parser(argparse.ArgumentParser):
    """argparse with the project's errors, and no abbreviated options: ``--frame`` is not
    silently taken for ``--frames`` (an option is spelled out, or refused)."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)

    def error(self, message):
        hint = f"usage: {self.usage}" if self.usage else f"{self.prog} --help lists the options and their ranges"
        raise UsageError(f"{message}\n{hint}")


def ranged(rng: Range, what: str = "value"):
    """An argparse ``type`` that parses a word with `rng` and refuses values outside it
    (argparse then says ``argument --dx: must be > 0, got -1``)."""

    def convert(text: str):
        try:
            value = rng.parse(text)
        except ValueError as err:
            raise argparse.ArgumentTypeError(str(err)) from None
        if not rng.accepts(value):
            raise argparse.ArgumentTypeError(f"must be {rng.describe()}, got {text}")
        return value

    convert.__name__ = what  # argparse names the type in some messages
    return convert


def ranged_list(rng: Range, what: str = "values"):
    """An argparse ``type`` for comma-separated values, each in `rng` (e.g. ``--rho0 1000,500``)."""

    def convert(text: str):
        words = text.split(",")
        values = []
        for word in words:
            try:
                value = rng.parse(word.strip())
            except ValueError:
                raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from None
            if not rng.accepts(value):
                raise argparse.ArgumentTypeError(f"each value must be {rng.describe()}, got {word.strip()} in {text}")
            values.append(value)
        return values

    convert.__name__ = what
    return convert


# the ranges of options shared by several commands
POSITIVE = ranged(positive, "positive number")
FRAMES = ranged(seed_frames, "frames")  # the seed's run command's
OUTPUT_FRAMES = ranged(output_frames, "frames")  # a run's: 0 writes the initial frame only
END_TIME = ranged(end_time, "end time")  # and of t_end
THREADS = ranged(integer(at_least=1), "threads")
EVERY = ranged(integer(at_least=1), "count")  # every K frames
NON_NEGATIVE = ranged(at_least(0), "non-negative number")
FRACTION = ranged(between(0, 1), "fraction")
COURANT = ranged(courant_number, "Courant number")
SKIN = ranged(between(0, 2), "skin")  # a fraction of the support radius (Scene.validate's range)
