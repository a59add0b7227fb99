"""Internal energy equation (seed eq. 11), for compressible flow.

Default (``form="compatible"``; Monaghan 1992, Price 2012 J. Comput. Phys. 231:759):

    de_a/dt = (P_a / rho_a^2) sum_b m_b (v_a - v_b) . grad_a W_ab

the form that goes with the symmetric pressure force of :mod:`pressure_gradient`:
together they conserve total energy sum_a m_a (e_a + v_a^2 / 2) exactly, pair by pair
(tests/test_gas.py checks the rates to round-off). ``form="seed"`` is the seed's
eq. 11 as written,

    de_a/dt = (P_a / rho_a) sum_b (m_b / rho_b) (v_a - v_b) . grad_a W_ab,

which is consistent but does not conserve energy exactly.

The artificial viscosity heats the gas (its ``+ 1/2 sum m_b Pi_ab v_ab . grad W``
term) and the artificial conductivity diffuses e: both add to the same rate, in their
own modules, whenever this term is in the scene. Fluid neighbours only.
"""

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .base import Term

FORMS = ("compatible", "seed")


@ti.data_oriented
class InternalEnergy(Term):
    name = "energy"
    scalars = ("energy",)
    integrates = {"energy": "d_energy"}
    wall_range = None  # fluid neighbours only

    def __init__(self, form: str = "compatible"):
        if form not in FORMS:
            raise ValueError(f"InternalEnergy form must be one of {', '.join(FORMS)}, got {form!r}")
        super().__init__()
        self.options = {"form": form}

    def check(self, scene):
        if self.options["form"] == "compatible" and "pressure" not in scene.terms_by_name:
            raise InputError("the compatible energy equation needs the pressure term (PressureGradient), "
                             "whose P/rho^2 it shares")

    def describe(self):
        return f"{self.name}(form={self.options['form']})"

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, grad, rates: ti.template()):
        q = ti.static(self.q)
        if s.Si[q.kind, j] == FLUID:
            vij_grad = (s.Sv[q.velocity, i] - s.Sv[q.velocity, j]).dot(grad)
            if ti.static(self.options["form"] == "compatible"):
                rates.d[self.r.d_energy] += s.Ss[q.mass, j] * s.Ss[q.p_over_rho2, i] * vij_grad
            else:
                rates.d[self.r.d_energy] += (s.Ss[q.pressure, i] / s.Ss[q.density, i]) * (
                    s.Ss[q.mass, j] / s.Ss[q.density, j]) * vij_grad
