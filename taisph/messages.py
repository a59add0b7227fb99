"""What taisph says besides its results, and where it goes.

Standard output carries results only (``$(python -m taisph ...)`` captures nothing
else); messages go to standard error:

- Taichi prints a banner (``[Taichi] version 1.7.4, llvm ...``) to standard output
  when it is imported. Importing this module before Taichi turns it off (Taichi's own
  switch, the environment variable ``ENABLE_TAICHI_HEADER_PRINT``; a value set by the
  user is kept), so ``taisph/__init__.py`` imports it first.
- taisph's warnings are :class:`TaisphWarning` (a ``UserWarning``), or
  :class:`TaisphRuntimeWarning` (also a ``RuntimeWarning``) for a run that may go
  wrong. In a program they are ordinary Python warnings; the command line calls
  :func:`install`, which prints them as one line, ``taisph: warning: MESSAGE``,
  instead of Python's file path, line number and source line. Other warnings are
  printed as before.
- taisph's refusals of input a user can correct (a parameter out of range, a scene
  that cannot be built, a file or folder that does not exist or does not read) are
  :class:`InputError` (a ``ValueError``). The command line prints one of them as one
  line, ``taisph: error: MESSAGE``, and exits with code 2; any other exception is a
  fault of taisph and keeps its traceback (exit code 1).
"""

from __future__ import annotations

import os
import warnings

# Taichi's switch for its import banner (taichi/_lib/utils.py), read when taichi is imported
os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "False")


class TaisphWarning(UserWarning):
    """A warning from taisph (printed as ``taisph: warning: ...`` once :func:`install` ran)."""


class TaisphRuntimeWarning(TaisphWarning, RuntimeWarning):
    """A taisph warning that a run may go wrong (e.g. a fixed dt above the stability limit);
    also a ``RuntimeWarning``, so filters and tests written for that still match."""


class InputError(ValueError):
    """Input a user can correct: exit code 2 on the command line, with ``str(err)`` as
    one line ``taisph: error: MESSAGE`` (so the message names what was given, the
    value and what is allowed). Still a ``ValueError``: Python callers that catch
    ``ValueError`` keep working. Raise it only for the user's input; a broken
    invariant inside taisph is any other exception, so it keeps its traceback."""


def format_warning(message, category, filename, lineno, line=None) -> str:
    """One line for a taisph warning; anything else as Python formats it."""
    if isinstance(category, type) and issubclass(category, TaisphWarning):
        return f"taisph: warning: {message}\n"
    return _python_format(message, category, filename, lineno, line)


_python_format = warnings.formatwarning


def install() -> None:
    """Print taisph's warnings as one line, ``taisph: warning: MESSAGE`` (the command
    line calls this first). Other warnings keep their format; calling it again changes
    nothing."""
    global _python_format
    if warnings.formatwarning is not format_warning:
        _python_format = warnings.formatwarning
        warnings.formatwarning = format_warning
