"""Surface tension: the continuum surface force (CSF) of Brackbill, Kothe & Zemach (1992) in SPH form.

    dv_i/dt += 2 sigma kappa_i grad c_i / (rho_1 + rho_2)

A colour function c is 1 in the scene's first material and 0 elsewhere. Its gradient
(Morris 2000, J. Comput. Phys. 33:333, eq. 17)

    grad c_i = sum_j V_j (c_j - c_i) grad_i W_ij          (V = m / rho; zero in the bulk)

points into the first material across the interface; n_i = grad c_i / |grad c_i| is the
interface normal where |grad c_i| > 0.05 / h (a "reliable" normal, Morris 2000 eq. 20,
who takes 0.01 / h; 0.05 / h holds the Laplace jump within 4 %, 0.1 / h and 0.2 / h lose 6 %:
docs/multiphase.md).
The curvature kappa = -div n is the trace of the corrected gradient of n (Bonet & Lok
1999, Comput. Methods Appl. Mech. Engrg. 180:97), exact for a linear field whatever the
neighbourhood,

    kappa_i = -tr(G_i L_i^-1),   G_i = sum_j V_j (n_j - n_i) (x) grad_i W_ij,
                                 L_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij,

over the neighbours whose normal is reliable too. These form a band a few particles
across the interface, which is far from the full, even neighbourhood the scalar
normalisation of Adami, Hu & Adams (2010, eq. 20) is exact on; the corrected gradient is
exact for a linear field on any neighbourhood. On a relaxed circular drop (R = 20 dx) it
reads kappa R = 1.02-1.03 across the band (docs/multiphase.md).

The force per unit volume sigma kappa grad c is scaled by 2 rho_i / (rho_1 + rho_2)
(Brackbill et al. 1992 eq. 41: the density-scaled CSF), rho_1 and rho_2 the smallest and
largest rho0: the acceleration is then the same on both sides of the interface, and the
light phase (air beside water, 1000 times lighter) is not thrown by a force its density
cannot carry, while the force summed across the interface is still sigma kappa per unit
area (half on each side).
``sigma`` (N/m) is a runtime value.

``free_surface=True``: a liquid without its gas phase (one material, the first). The void
beyond the surface counts as colour 0: grad c_i = sum_j V_j c_j grad_i W_ij over the
liquid and the walls (a wall counts as liquid: the surface meets it at 90 degrees), which
is the same sum where the kernel is full and the missing void's share at the surface.

Why this model (docs/multiphase.md): it applies the tension where the interface is and
in proportion to each side's density, so it works at physical values (water's sigma =
0.0728 N/m, a millimetre drop, air at 1/830 of water's density). It is not momentum-
conserving pair by pair (a closed interface's forces sum to zero only as the curvature
converges). Wall adhesion (a contact angle) is not modelled.

The time step: dt <= 0.25 sqrt(rho h^3 / (2 pi sigma)), the capillary-wave limit of
Brackbill et al. (1992) eq. 61, with rho the mean of the smallest and largest rho0.
"""

import math

import taichi as ti

from ..engine.layout import FLUID
from ..messages import InputError
from .base import NeighbourPass, VolumeTerm

RELIABLE = 0.05  # a normal is reliable where |grad c| > RELIABLE / h (Morris 2000 eq. 20; see above)


@ti.data_oriented
class SurfaceTension(VolumeTerm):
    name = "surface_tension"
    params = {"sigma": None}
    vectors = ("colour_gradient",)
    scalars = ("volume", "curvature")
    # the colour gradient and curvature are kept with the state (not derived) so that frames and
    # readouts show the values the last step used
    outputs = ("curvature",)

    def __init__(self, free_surface: bool = False, **values):
        super().__init__(**values)
        self.options["free_surface"] = bool(free_surface)
        # the free-surface form counts walls as liquid in the colour gradient
        self.wall_range = "support" if free_surface else None

    @property
    def free_surface(self) -> bool:
        return self.options["free_surface"]

    def check(self, scene):
        sigma = self.values.get("sigma")
        if sigma is None or not (isinstance(sigma, (int, float)) and math.isfinite(sigma) and sigma >= 0):
            raise InputError(f"surface_tension needs a surface tension coefficient sigma >= 0 (N/m), got {sigma!r}")
        if self.free_surface and len(scene.materials) > 1:
            raise InputError("surface_tension(free_surface=True) is for one liquid without its gas phase; with "
                             f"{len(scene.materials)} materials use the two-phase form (free_surface=False)")
        if not self.free_surface and len(scene.materials) < 2:
            raise InputError("surface_tension acts between phases and the scene has one material: for a liquid "
                             "without its gas phase use SurfaceTension(free_surface=True) (what a scene file's "
                             "physics.surface_tension gives a fluid of one material)")

    def passes(self):
        return [_ColourGradient(self), _Curvature(self)]

    @ti.func
    def particle(self, s: ti.template(), i, rates: ti.template()):
        lo, hi = density_range(s, self.m.rho0, self.material_count(s))
        rates.acc += (2.0 * s.params[self.p.sigma] * s.Ss[self.q.curvature, i] / (lo + hi)) \
            * s.Sv[self.q.colour_gradient, i]

    @ti.func
    def step_limit(self, s: ti.template()):
        lo, hi = density_range(s, self.m.rho0, self.material_count(s))
        return capillary_limit_device(ti.cast(s.params[self.p_h], ti.f64), ti.cast(0.5 * (lo + hi), ti.f64),
                               ti.cast(s.params[self.p.sigma], ti.f64))

    def host_step_limit(self, scene, controls) -> float:
        rho = [m.rho0 for m in scene.materials]
        return float(capillary_limit(scene.smoothing_length, 0.5 * (min(rho) + max(rho)), float(self.values["sigma"])))


def capillary_limit(h, rho, sigma):
    """0.25 sqrt(rho h^3 / (2 pi sigma)) (no limit, ~1e150 s, for sigma = 0); Python numbers
    or, in a kernel, f64 values."""
    return 0.25 * ti.sqrt(rho * h * h * h / (2.0 * math.pi * ti.max(sigma, 1e-300)))


capillary_limit_device = ti.func(capillary_limit)


@ti.func
def density_range(s: ti.template(), rho0_col, count):
    """The smallest and the largest rho0 of the `count` materials."""
    lo = s.mat[0, rho0_col]
    hi = lo
    for k in range(1, count):
        lo = ti.min(lo, s.mat[k, rho0_col])
        hi = ti.max(hi, s.mat[k, rho0_col])
    return lo, hi


@ti.data_oriented
class _ColourGradient(NeighbourPass):
    """grad c_i (see the module docstring), stored in the ``colour_gradient`` row."""

    select = "fluid"

    def __init__(self, term):
        self.q = term.q
        self.free_surface = term.free_surface

    @ti.func
    def init(self, s: ti.template(), i):
        return s.Sv[self.q.position, i] * 0.0

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        q = ti.static(self.q)
        weight = 0.0  # V_j (c_j - c_i), or V_j c_j at a free surface
        if ti.static(self.free_surface):  # the void beyond the surface has colour 0, the liquid and walls 1
            weight = s.Ss[q.mass, j] / s.Ss[q.density, j]
        elif s.Si[q.kind, j] == FLUID:
            c_i = 1.0 if s.Si[q.material, i] == 0 else 0.0
            c_j = 1.0 if s.Si[q.material, j] == 0 else 0.0
            weight = s.Ss[q.mass, j] / s.Ss[q.density, j] * (c_j - c_i)
        for d in ti.static(range(grad.n)):  # acc is the caller's: update it in place
            acc[d] += weight * grad[d]

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        s.Sv[self.q.colour_gradient, i] = acc


@ti.data_oriented
class _Curvature(NeighbourPass):
    """kappa_i = -div n with the corrected gradient, over reliable normals."""

    select = "fluid"

    def __init__(self, term):
        self.q = term.q
        self.p_h = term.p_h

    @ti.func
    def normal(self, s: ti.template(), i):
        """(unit normal, reliable?) of particle i."""
        c = s.Sv[self.q.colour_gradient, i]
        size = c.norm()
        reliable = size * s.params[self.p_h] > RELIABLE
        n = c * 0.0
        if reliable:
            n = c / size
        return n, reliable

    @ti.func
    def init(self, s: ti.template(), i):
        # G = sum V_j (n_j - n_i) (x) grad W_ij and L = sum V_j (x_j - x_i) (x) grad W_ij, row-major
        dim = ti.static(s.Sv[self.q.position, i].n)
        return ti.Vector([0.0] * (2 * dim * dim))

    @ti.func
    def pair(self, s: ti.template(), i, j, rij, r, w, grad, acc: ti.template()):
        q = ti.static(self.q)
        dim = ti.static(rij.n)
        if s.Si[q.kind, j] == FLUID:
            n_i, ok_i = self.normal(s, i)
            n_j, ok_j = self.normal(s, j)
            if ok_i and ok_j:
                volume = s.Ss[q.mass, j] / s.Ss[q.density, j]
                dn = volume * (n_j - n_i)
                dx = -volume * rij
                for a in ti.static(range(dim)):
                    for b in ti.static(range(dim)):
                        acc[a * dim + b] += dn[a] * grad[b]
                        acc[dim * dim + a * dim + b] += dx[a] * grad[b]

    @ti.func
    def finish(self, s: ti.template(), i, acc):
        dim = ti.static(s.Sv[self.q.position, i].n)
        g = ti.Matrix([[acc[a * dim + b] for b in ti.static(range(dim))] for a in ti.static(range(dim))])
        lm = ti.Matrix([[acc[dim * dim + a * dim + b] for b in ti.static(range(dim))] for a in ti.static(range(dim))])
        kappa = 0.0
        # L is -I for a full, even neighbourhood; a band of reliable normals only a few particles
        # across still spans every direction, but one or two neighbours do not: no curvature there
        if ti.abs(lm.determinant()) > MIN_DETERMINANT:
            kappa = -(g @ lm.inverse()).trace()
        s.Ss[self.q.curvature, i] = kappa


MIN_DETERMINANT = 0.1  # of L, the neighbourhood's first moment (-I when the kernel is full)
