"""The seed's text files (APC524 report, sections 3.1-3.2): particles in, ``fluid.dat`` out.

Particle file (and boundary file, same format)::

    N                                                  first line: the particle count
    index x y u v mass density pressure energy         N lines, indices 0 .. N-1

3D extension (taisph): 11 columns, ``index x y z u v w mass density pressure
energy``. The number of columns of the first particle line sets the dimension (9:
2D, 11: 3D); every line must then have that many (or pass ``dim`` to insist).

Output (``fluid.dat``): for each output time a header line, then the same columns
for every fluid particle, in index order::

    [Timestep k] time = t
    index x y u v mass density pressure energy
    ...

``[Timestep 0]`` is the initial state; ``k`` counts output frames and ``time`` is
the simulated time in seconds. Values are written with 17 significant digits, so a
file read back gives the same float64 numbers.

Reading is strict: a problem raises :class:`SeedFileError` naming the file, the
line, the column and the offending text (a wrong count, missing or extra columns,
text that is not a number, NaN or infinite values, non-positive mass or density,
indices that are not whole numbers in 0 .. N-1 or appear twice, an empty file).
Blank lines are ignored.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..messages import InputError
from ..scene.parameters import particle_mass, position_component, reference_density, velocity_component

COLUMNS = {
    2: ("index", "x", "y", "u", "v", "mass", "density", "pressure", "energy"),
    3: ("index", "x", "y", "z", "u", "v", "w", "mass", "density", "pressure", "energy"),
}
DIM_OF_COLUMNS = {len(c): d for d, c in COLUMNS.items()}


class SeedFileError(InputError):
    """Bad input in a seed-format file, or one that does not exist or does not read:
    ``str(err)`` names the file, the line and the value (an
    :class:`taisph.messages.InputError`: exit code 2 on the command line)."""

    def __init__(self, path, message: str, line: int | None = None):
        self.path = str(path)
        self.line = line
        self.reason = message
        where = f"{self.path}, line {line}" if line is not None else self.path
        super().__init__(f"{where}: {message}")


@dataclass
class ParticleData:
    """Particles of a seed-format file, sorted by index (row k has index k).

    ``position``, ``velocity``: (N, dim); ``mass``, ``density``, ``pressure``,
    ``energy``: (N,); ``line``: (N,) the line each particle was read from.
    """

    path: str
    dim: int
    position: np.ndarray
    velocity: np.ndarray
    mass: np.ndarray
    density: np.ndarray
    pressure: np.ndarray
    energy: np.ndarray
    line: np.ndarray

    @property
    def n(self) -> int:
        return len(self.mass)


# Lines end at \n, \r\n or \r, as editors, grep -n and Python's text mode count them (not at
# the other breaks of str.splitlines: \x0b, \x0c, \x1c-\x1e, \x85, U+2028, U+2029); values are
# separated by spaces and tabs (and Unicode spaces); any other control character (or a line or
# paragraph separator) is part of a token, a bad one
_LINE_END = re.compile(r"\r\n|\r|\n")
_CONTROL = re.compile("[\x00-\x08\x0a-\x1f\x7f-\x9f\u2028\u2029]")
_SEPARATOR = re.compile("[^\\S\x00-\x08\x0a-\x1f\x7f-\x9f\u2028\u2029]+")
# Bounds of the values of a particle line (taisph.scene.parameters' shared ranges): beyond them
# a scene's sizes overflow (h^(dim+2) of a mass of 1e300) or its scales are absurd
_BOUNDS = {"position": position_component, "velocity": velocity_component, "mass": particle_mass,
           "density": reference_density}


def _columns_text(dim: int) -> str:
    return f"{len(COLUMNS[dim])} columns ({dim}D: {' '.join(COLUMNS[dim])})"


def _parse_whole(text: str):
    """int of `text` if it is a whole number ("12", "12.0", "1.2e1"), else None."""
    try:
        return int(text)
    except ValueError:
        pass
    try:
        value = float(text)
    except ValueError:
        return None
    if math.isfinite(value) and value == int(value):
        return int(value)
    return None


def read_particles(path, dim: int | None = None, what: str = "particle file",
                   allow_empty: bool = False) -> ParticleData:
    """Read a seed-format particle (or boundary) file; raise :class:`SeedFileError`.

    `dim` (2 or 3) insists on that many coordinates; None detects it from the
    column count of the first particle line. `allow_empty` accepts a count of 0.
    """
    path = Path(path)
    if dim is not None and dim not in COLUMNS:
        raise ValueError(f"dim must be 2 or 3, got {dim!r}")
    lines = _token_lines(path, what)
    count, body = _count(path, lines, what, allow_empty)
    if count == 0:
        d = dim or 2
        z = np.zeros((0, d))
        e = np.zeros(0)
        return ParticleData(str(path), d, z, z.copy(), e, e.copy(), e.copy(), e.copy(), np.zeros(0, int))
    dim, names = _columns(path, body, dim)
    rows = [tokens for _, tokens in body]
    line_of = np.array([k for k, _ in body])
    data = _numbers(path, body, names)
    order = _index_order(path, data[:, 0], rows, line_of, count)
    _check_values(path, data, rows, line_of, names)
    data = data[order]
    col = {name: k for k, name in enumerate(names)}
    xyz = [col[a] for a in ("x", "y", "z")[:dim]]
    uvw = [col[a] for a in ("u", "v", "w")[:dim]]
    return ParticleData(
        path=str(path),
        dim=dim,
        position=data[:, xyz].copy(),
        velocity=data[:, uvw].copy(),
        mass=data[:, col["mass"]].copy(),
        density=data[:, col["density"]].copy(),
        pressure=data[:, col["pressure"]].copy(),
        energy=data[:, col["energy"]].copy(),
        line=line_of[order],
    )


def _token_lines(path: Path, what: str) -> list:
    """The file's non-blank lines as (line number, tokens); refuses a file that does not
    read, is not UTF-8 text, holds a control character in a token, or is empty."""
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise SeedFileError(path, f"no such {what}") from None
    except IsADirectoryError:
        raise SeedFileError(path, f"is a directory, not a {what}") from None
    except OSError as err:
        raise SeedFileError(path, f"cannot read the {what}: {err.strerror}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SeedFileError(path, f"is not a text file (byte {err.start} is not UTF-8)") from None
    lines = []
    for k, line in enumerate(_LINE_END.split(text), start=1):
        tokens = [t for t in _SEPARATOR.split(line) if t]
        for c, tok in enumerate(tokens):
            bad = _CONTROL.search(tok)
            if bad:
                raise SeedFileError(path, f"column {c + 1} is {tok!r}, which holds the control character "
                                          f"U+{ord(bad[0]):04X}; a line holds numbers separated by spaces or tabs",
                                    k)
        if tokens:
            lines.append((k, tokens))
    if not lines:
        raise SeedFileError(path, f"the {what} is empty; its first line must be the particle count")
    return lines


def _count(path: Path, lines: list, what: str, allow_empty: bool) -> tuple:
    """(count, particle lines): the count of the first line, which the particle lines
    that follow it must match."""
    count_line, tokens = lines[0]
    if len(tokens) != 1:
        hint = " (is the count line missing?)" if len(tokens) in DIM_OF_COLUMNS else ""
        raise SeedFileError(path, f"the first line must hold only the particle count, found {len(tokens)} "
                                  f"values {' '.join(tokens[:4])}{' ...' if len(tokens) > 4 else ''}{hint}",
                            count_line)
    count = _parse_whole(tokens[0])
    if count is None or count < 0:
        raise SeedFileError(path, f"the particle count {tokens[0]!r} is not a whole number >= 0", count_line)
    if count == 0 and not allow_empty:
        raise SeedFileError(path, f"the particle count is 0; a {what} needs at least one particle", count_line)
    body = lines[1:]
    if len(body) > count:
        extra_line = body[count][0]
        raise SeedFileError(path, f"extra particle line: the first line announces {count} particle(s), "
                                  f"but the file has {len(body)} particle lines", extra_line)
    if len(body) < count:
        last = body[-1][0] if body else count_line
        raise SeedFileError(path, f"the file ends after {len(body)} particle line(s), but the first line "
                                  f"(line {count_line}) announces {count}", last)
    return count, body


def _columns(path: Path, body: list, dim: int | None) -> tuple:
    """(dim, column names): `dim`, or the one the first particle line's column count
    sets; every particle line must have that many columns."""
    first_line, first_tokens = body[0]
    if dim is None:
        dim = DIM_OF_COLUMNS.get(len(first_tokens))
        if dim is None:
            raise SeedFileError(path, f"found {len(first_tokens)} columns; a particle line has "
                                      f"{_columns_text(2)} or {_columns_text(3)}", first_line)
        set_by = f"; the first particle line, line {first_line}, has {len(first_tokens)} and sets the dimension"
    else:
        set_by = ""
    names = COLUMNS[dim]
    ncol = len(names)
    for k, tokens in body:
        if len(tokens) != ncol:
            kind = "missing" if len(tokens) < ncol else "extra"
            raise SeedFileError(path, f"{kind} columns: found {len(tokens)}, expected {ncol} "
                                      f"({dim}D: {' '.join(names)}{set_by})", k)
    return dim, names


def _numbers(path: Path, body: list, names) -> np.ndarray:
    """The particle lines as an (N, columns) array of finite numbers (a fast conversion;
    if it fails, the first token that is not a number is found and named)."""
    rows = [tokens for _, tokens in body]
    try:
        data = np.array(rows, dtype=float)
    except ValueError:
        data = None
    if data is None:
        for (k, tokens) in body:
            for c, tok in enumerate(tokens):
                try:
                    float(tok)
                except ValueError:
                    raise SeedFileError(path, f"column {c + 1} ({names[c]}) is {tok!r}, not a number", k) from None
        raise SeedFileError(path, "could not read the numbers")  # pragma: no cover
    bad = ~np.isfinite(data)
    if bad.any():
        r, c = np.argwhere(bad)[0]
        raise SeedFileError(path, f"column {c + 1} ({names[c]}) is {rows[r][c]!r}; values must be finite numbers",
                            int(body[r][0]))
    return data


def _index_order(path: Path, index: np.ndarray, rows: list, line_of: np.ndarray, count: int) -> np.ndarray:
    """The order that sorts the particle lines by index; the indices must be whole
    numbers in 0 .. count - 1, each once."""
    not_whole = index != np.round(index)
    if not_whole.any():
        r = int(np.flatnonzero(not_whole)[0])
        raise SeedFileError(path, f"column 1 (index) is {rows[r][0]!r}, not a whole number", int(line_of[r]))
    out_of_range = (index < 0) | (index >= count)  # (before the cast: 1e19 has no int64)
    if out_of_range.any():
        r = int(np.flatnonzero(out_of_range)[0])
        raise SeedFileError(path, f"index {rows[r][0]} is out of range: with {count} particle(s) the indices "
                                  f"run from 0 to {count - 1}", int(line_of[r]))
    index = index.astype(np.int64)
    order = np.argsort(index, kind="stable")
    dup = np.flatnonzero(index[order][1:] == index[order][:-1])
    if dup.size:
        first, second = sorted((order[dup[0]], order[dup[0] + 1]))
        raise SeedFileError(path, f"index {index[second]} is used twice (also on line {line_of[first]})",
                            int(line_of[second]))
    return order


def _check_values(path: Path, data: np.ndarray, rows: list, line_of: np.ndarray, names) -> None:
    """Physical values: mass and density > 0, then every position, velocity, mass and
    density within its bounds (:data:`_BOUNDS`; the first bad value in file order)."""
    for name in ("mass", "density"):
        c = names.index(name)
        bad = np.flatnonzero(data[:, c] <= 0)
        if bad.size:
            r = int(bad[0])
            raise SeedFileError(path, f"column {c + 1} ({name}) is {rows[r][c]}; it must be > 0", int(line_of[r]))

    for k, name in enumerate(names):
        kind = {"x": "position", "y": "position", "z": "position", "u": "velocity", "v": "velocity",
                "w": "velocity"}.get(name, name)
        rng = _BOUNDS.get(kind)
        if rng is None:
            continue
        bad = np.flatnonzero(~((data[:, k] >= rng.low) & (data[:, k] <= rng.high)))
        if bad.size:
            r = int(bad[0])
            raise SeedFileError(path, f"column {k + 1} ({name}) is {rows[r][k]!r}; a particle's {kind} "
                                      f"{'component ' if kind in ('position', 'velocity') else ''}must be "
                                      f"{rng.describe()}", int(line_of[r]))


def _rows(position, velocity, mass, density, pressure, energy, index=None) -> np.ndarray:
    position = np.asarray(position, float)
    n, dim = position.shape
    if dim not in COLUMNS:
        raise ValueError(f"the seed format is 2D or 3D (11 columns), got {dim} coordinates")
    index = np.arange(n) if index is None else np.asarray(index)
    energy = 0.0 if energy is None else energy
    scalars = [np.broadcast_to(np.asarray(a, float), (n,)) for a in (mass, density, pressure, energy)]
    return np.column_stack([index, position, np.broadcast_to(np.asarray(velocity, float), (n, dim)), *scalars])


def _format(dim: int) -> str:
    return " ".join(["%d"] + ["%.17g"] * (len(COLUMNS[dim]) - 1))


def write_particles(path, position, velocity, mass, density, pressure, energy=None) -> Path:
    """Write a seed-format particle file (indices 0 .. N-1), atomically: the count,
    then ``index x y [z] u v [w] mass density pressure energy`` per particle."""
    path = Path(path)
    rows = _rows(position, velocity, mass, density, pressure, energy)
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "w") as f:
        f.write(f"{len(rows)}\n")
        np.savetxt(f, rows, fmt=_format(rows.shape[1] == 11 and 3 or 2))
    os.replace(tmp, path)
    return path


class OutputWriter:
    """Appends frames to a seed-format output file (``fluid.dat``)."""

    def __init__(self, path):
        self.path = Path(path)
        self.frames = 0
        self._file = open(self.path, "w")

    def write(self, time: float, position, velocity, mass, density, pressure, energy=None, index=None):
        rows = _rows(position, velocity, mass, density, pressure, energy, index)
        self._file.write(f"[Timestep {self.frames}] time = {time!r}\n")
        np.savetxt(self._file, rows, fmt=_format(3 if rows.shape[1] == 11 else 2))
        self._file.flush()
        self.frames += 1

    def close(self):
        if not self._file.closed:
            self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


@dataclass
class OutputFrame:
    step: int
    time: float
    index: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    mass: np.ndarray
    density: np.ndarray
    pressure: np.ndarray
    energy: np.ndarray


def read_output(path) -> list[OutputFrame]:
    """Frames of a ``fluid.dat`` written by taisph (or the seed: a header without
    ``time =`` gives time NaN)."""
    path = Path(path)
    frames = []
    header = None
    rows: list = []

    def close_frame():
        if header is None:
            return
        data = np.array(rows, dtype=float).reshape(len(rows), -1)
        dim = DIM_OF_COLUMNS.get(data.shape[1], 2) if len(rows) else 2
        names = COLUMNS[dim]
        col = {name: k for k, name in enumerate(names)}
        frames.append(OutputFrame(
            step=header[0], time=header[1], index=data[:, 0].astype(int) if len(rows) else np.zeros(0, int),
            position=data[:, [col[a] for a in ("x", "y", "z")[:dim]]] if len(rows) else np.zeros((0, dim)),
            velocity=data[:, [col[a] for a in ("u", "v", "w")[:dim]]] if len(rows) else np.zeros((0, dim)),
            **{name: (data[:, col[name]] if len(rows) else np.zeros(0))
               for name in ("mass", "density", "pressure", "energy")},
        ))

    with open(path) as f:
        for k, line in enumerate(f, start=1):
            s = line.strip()
            if not s:
                continue
            if s.startswith("[Timestep"):
                close_frame()
                head, _, rest = s.partition("]")
                try:
                    step = int(head[len("[Timestep"):].strip())
                except ValueError:
                    raise SeedFileError(path, f"bad frame header {s!r}", k) from None
                time = float("nan")
                if "=" in rest:
                    time = float(rest.split("=", 1)[1])
                header = (step, time)
                rows = []
            else:
                if header is None:
                    raise SeedFileError(path, "data before the first [Timestep k] header", k)
                rows.append(s.split())
    close_frame()
    return frames
