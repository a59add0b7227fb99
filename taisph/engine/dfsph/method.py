"""DFSPH's method (``Scene(solver="dfsph")``): what the engine asks of it (the interface,
:class:`taisph.engine.method.Method`), from its solve (:mod:`.solver`), its parameters
(:mod:`.parameters`), its pair list (:mod:`.pairs`) and its diagnosis (:mod:`.diagnosis`).

It compiles the scene's non-pressure terms (:data:`taisph.scene.solvers.DFSPH_KEPT`),
no equation of state (:class:`.solver.Incompressible`), symplectic Euler, and a step
that iterates its two solves from the host (:class:`.solver.Stepper`); its time step
follows the flow speed, not the sound speed (dt = C h / max |v|), and its speed guard is
on by default (an incompressible solve keeps the density of a particle it kicks away, so
a speed is what shows its failure: docs/dfsph.md).
"""

from dataclasses import dataclass

import taichi as ti

from ...scene.parameters import Number, at_least, integer
from ...scene.solvers import dfsph_kept_terms
from ..method import Method
from . import diagnosis, pairs, parameters
from .solver import CHUNKS, Extra, Incompressible, Stepper, initial_kappa, rows

# Its CFL number (dt = C h / max |v|; the scene's Courant number is the weakly compressible
# solver's): 0.5 h = 0.65 dx, where Bender & Koschier use 0.4 particle diameters (0.3 h);
# the measurements behind 0.5 are in docs/dfsph.md, "Time step"
DFSPH_COURANT = 0.5
# and its force factor (dt <= C sqrt(h / |g|): it tracks the body forces only, the viscous
# terms have their viscous limit): the pressure solve converges from rest with 0.1, not with
# the weakly compressible 0.25 (docs/dfsph.md, "Time step")
DFSPH_FORCE_FACTOR = 0.1


@dataclass
class SolveControls:
    """DFSPH's pressure solves (:class:`taisph.engine.dfsph.solver.Stepper`; docs/dfsph.md):

    dfsph_tolerance    mean density error a constant-density solve stops at (fraction of rho0)
    dfsph_divergence_tolerance   mean density change per step a divergence solve stops at
    dfsph_min_iterations, dfsph_max_iterations   iterations of the constant-density solve
                       at least (the divergence solve: 1) and of either solve at most
    dfsph_error_bound  a solve that reaches the maximum iterations above its tolerance but
                       within this many times it is kept (and counted: Stats.above_tolerance); beyond,
                       the step is retried with half the dt, up to dfsph_retries times, before the run
                       stops with the diagnosis (taisph.engine.dfsph.diagnosis)
    dfsph_retries      how many times a step whose solve ended beyond the bound is retried, each
                       time with half the last dt
    """

    # 0.02 %, not Bender & Koschier's 0.1 %: a closer front for a little more wall time; the
    # first steps from rest take the most iterations, hence 300 (docs/dfsph.md, "Tolerance")
    dfsph_tolerance: float = 0.0002
    dfsph_divergence_tolerance: float = 0.001
    dfsph_min_iterations: int = 2
    dfsph_max_iterations: int = 300
    # an error within 10x the tolerance is still a 0.2 % compression (docs/dfsph.md: why 10)
    dfsph_error_bound: float = 10.0
    dfsph_retries: int = 3


class DFSPH(Method):
    name = "dfsph"
    pressure_derived = False  # the solve's pressure, written at the end of every step
    params = parameters.PARAMS
    Controls = SolveControls
    ranges = {
        "dfsph_tolerance": Number(0, 1, low_open=True),
        "dfsph_divergence_tolerance": Number(0, 1, low_open=True),
        "dfsph_min_iterations": integer(at_least=1, at_most=100_000),
        "dfsph_max_iterations": integer(at_least=1, at_most=100_000),
        "dfsph_error_bound": at_least(1),
        "dfsph_retries": integer(at_least=0, at_most=20),
    }
    acoustic = False  # incompressible: the step follows the flow speed
    viscosity_params = ("dfsph_nu_art",)  # artificial viscosity's equivalent (parameters.py)
    # the summation density is short of rho0 at a free surface by design: only compression counts
    compression_only = True

    def terms(self, scene) -> list:
        return dfsph_kept_terms(scene)

    def eos(self, scene):
        return Incompressible()

    def integrator(self, scene) -> str:
        return "euler"

    def rows(self, terms, has_shift: bool) -> tuple:
        return rows(has_shift, any(t.with_walls for t in terms))

    def parameter_values(self, scene, controls) -> dict:
        return parameters.parameter_values(scene, controls)

    def extra_fields(self, solver, field, capacity: int, list_capacity: int):
        """Its pair list and error sums (:class:`.solver.Extra`)."""
        return Extra(pairs=pairs.allocate(field, capacity, list_capacity, solver.real),
                     part=field(ti.f64, (CHUNKS, 2)), result=field(ti.f64, (4,)))

    def step_kernels(self, solver, fields, serial_sort: bool) -> tuple:
        """One callable, :class:`.solver.Stepper`, which iterates the solves."""
        return fields.kernel(("dfsph", serial_sort), lambda args: (Stepper(solver, fields, serial_sort),))

    def stepper(self, solver, fields, serial_sort: bool):
        return self.step_kernels(solver, fields, serial_sort)[0]

    def control_defaults(self, scene) -> dict:
        return dict(courant=DFSPH_COURANT, force_factor=DFSPH_FORCE_FACTOR)

    def max_speed(self, scene) -> float:
        """The largest material c0 (the cases set it to 10x the flow's speed)."""
        return max(float(getattr(m, "c0", 0.0) or 0.0) for m in scene.materials)

    def list_capacity(self, scene) -> int:
        return pairs.capacity(scene)

    def list_bytes(self, entries: int, real_bytes: int) -> int:
        return pairs.bytes_per_particle(entries, real_bytes)

    def initial_values(self, scene) -> dict:
        """The first solve starts from the scene's pressure (its initial density)."""
        return dict(kappa=initial_kappa(scene))

    def causes(self, code: str, sim, report) -> list | None:
        return diagnosis.causes(code, sim, report)


METHOD = DFSPH()
