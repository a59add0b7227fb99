"""The weakly compressible method: every term of the scene and its equation of state,
the pressure from the density (Monaghan 1994, 2005), integrated by the scene's
integrator; a step is the engine's kernels (:mod:`taisph.engine.kernels`).

One step on a field set, in order: the sort (the time step, the predictor, the
counting sort, the derived rows), the terms' ``after_sort`` launches, the neighbour
passes, the force pass (rates, update, time-step maxima, guards), and the terms'
``after_force`` launches (:mod:`taisph.terms.base`: what a subsystem declares).
The time step follows the sound speed: dt = C h / max(c + |v|) with the
scene's Courant number, if it has one (``Scene.courant``).
"""

from .. import kernels
from ..method import Method


class WCSPH(Method):
    name = "wcsph"

    def terms(self, scene) -> list:
        return list(scene.terms)

    def eos(self, scene):
        return scene.eos

    def integrator(self, scene) -> str:
        return scene.integrator

    def control_defaults(self, scene) -> dict:
        return dict(courant=getattr(scene, "courant", None))

    def step_kernels(self, solver, fields, serial_sort: bool) -> tuple:
        def build(args):  # only on the first call for these fields: the step's hot path is the cache lookup
            # terms with launches of their own (terms/base.py: after_sort, after_force)
            before = [t.after_sort(solver) for t in solver.ordered("after_sort")]
            after = [t.after_force(solver) for t in solver.ordered("after_force")]
            bodies = [kernels.sort_body(solver, serial_sort), *before,
                      *[kernels.pass_body(solver, p) for p in solver.passes], kernels.force_body(solver), *after]
            return tuple(solver.make_kernel(b)(args) for b in bodies)

        return fields.kernel(("step", serial_sort), build)


METHOD = WCSPH()
