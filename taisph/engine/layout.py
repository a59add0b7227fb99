"""Which per-particle quantities a simulation stores, and where.

Particle state is structure-of-arrays: every quantity is one contiguous array over
particles. Quantities of one type are stacked as the rows of one Taichi field,
``vectors[k, n]``, ``scalars[k, n]``, ``integers[k, n]`` (:mod:`.fields`), so that the
kernels see the same three fields whatever effects a scene enables: the row ``k`` of a
quantity is a compile-time constant, and a disabled effect's quantity simply has no
row (no memory).

Base quantities (always present)::

    vectors:  position, velocity
    scalars:  density, pressure, mass
    integers: id (persistent: data is reordered by cell every step), material, kind

Terms, the equation of state and the integrator add rows (e.g. the predictor-
corrector keeps last step's rates ``acc_prev``, ``d_density_prev``).

*Derived* quantities (pressure, sound speed, P/rho^2, a wall's extrapolated velocity...)
are recomputed from the state every step, after the state is gathered in cell order:
the step copies only the other, *carried*, rows from one buffer to the other.

A variable smoothing length is the scalar ``h`` (:data:`VARIABLE_H`), stored by the
term that sets it (:mod:`taisph.terms.smoothing_length`). Its presence switches the
neighbour sums, at compile time, from the scene's constant h to per-particle values.
"""

from __future__ import annotations

import collections

FLUID = 0
WALL = 1
REMOVED = 2  # a fluid particle taken out of the simulation (left an open domain)
KINDS = {"fluid": FLUID, "wall": WALL}

BASE_VECTORS = ("position", "velocity")
BASE_SCALARS = ("density", "pressure", "mass")
BASE_INTEGERS = ("id", "material", "kind")
VARIABLE_H = "h"  # per-particle smoothing length, when a term varies it


class Layout:
    """Row indices of every stored quantity; ``layout.q.name`` is the row of ``name``."""

    def __init__(self, vectors=(), scalars=(), integers=(), derived=(), pressure_derived=True):
        self.vectors = _unique(BASE_VECTORS + tuple(vectors))
        self.scalars = _unique(BASE_SCALARS + tuple(scalars))
        self.integers = _unique(BASE_INTEGERS + tuple(integers))
        # the equation of state's output (a method whose pressure comes from its solve keeps it)
        self.derived = frozenset(derived) | ({"pressure"} if pressure_derived else set())
        # rows a step carries from one buffer to the other (all but the derived ones)
        self.carried = tuple(tuple(k for k, name in enumerate(group) if name not in self.derived)
                             for group in (self.vectors, self.scalars, self.integers))
        rows = {}
        for group in (self.vectors, self.scalars, self.integers):
            for k, name in enumerate(group):
                if name in rows:
                    raise ValueError(f"quantity {name!r} declared with two types")
                rows[name] = k
        # a namedtuple, so kernels can take it with ti.static(self.q)
        self.q = collections.namedtuple("Rows", list(rows))(**rows)

    def kind_of(self, name: str) -> str:
        for kind, group in (("vector", self.vectors), ("scalar", self.scalars), ("integer", self.integers)):
            if name in group:
                return kind
        raise KeyError(name)


def _unique(names):
    seen = []
    for n in names:
        if n not in seen:
            seen.append(n)
    return tuple(seen)
