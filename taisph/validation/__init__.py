"""Validation of taisph against exact solutions and experiments (docs/validation.md).

:mod:`taisph.validation.runs` runs a case and measures its error against its reference;
:mod:`taisph.validation.references` holds the references (analytic solutions, the exact
Riemann solver, the Sedov-Taylor similarity solution, experimental data);
:mod:`taisph.validation.accuracy_cost` is the work-precision study over them
(``python -m tools.studies.accuracy_cost``), and :mod:`taisph.validation.seed_scenes` the
resolutions and recorder with which the seed's three scenes are measured (the tests
and ``python -m tools.studies.seed_measure``).
"""

from .runs import (VALIDATIONS, Outcome, couette, dam_break, elliptical_drop, hydrostatic_tank, poiseuille, reference,
                   run, taylor_green)

__all__ = ["VALIDATIONS", "Outcome", "run", "reference", "dam_break", "hydrostatic_tank", "poiseuille",
           "couette", "taylor_green", "elliptical_drop"]
