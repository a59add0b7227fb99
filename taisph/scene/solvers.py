"""What each solver accepts of a scene, as rules on the scene's terms: DFSPH keeps the
non-pressure forces and replaces the equation of state and the pressure terms by its
pressure solve (its method, :mod:`taisph.engine.dfsph.method`, compiles the terms kept;
the weakly compressible solver accepts every term)."""

from ..messages import InputError

# the terms of a scene that DFSPH keeps (non-pressure forces), and those it replaces
DFSPH_KEPT = ("gravity", "laminar_viscosity", "xsph", "artificial_viscosity")
DFSPH_REPLACED = ("continuity", "summation_density", "pressure", "density_diffusion", "dummy_walls", "riemann")


def dfsph_kept_terms(scene) -> list:
    """The scene's terms DFSPH simulates, in the scene's order."""
    return [t for t in scene.terms if t.name in DFSPH_KEPT]


def check_dfsph(scene):
    """Refuse a scene DFSPH cannot run (:class:`InputError`), saying what to change."""
    for t in scene.terms:
        if t.name not in DFSPH_KEPT and t.name not in DFSPH_REPLACED:
            raise InputError(f"scene {scene.name!r}: the term {t.name!r} cannot be used with solver='dfsph' "
                             f"(DFSPH keeps {', '.join(DFSPH_KEPT)} and replaces {', '.join(DFSPH_REPLACED)} by its "
                             "pressure solve); remove it or use solver='wcsph'")
    if getattr(scene.eos, "name", "") != "tait":
        raise InputError(f"scene {scene.name!r}: solver='dfsph' simulates incompressible liquids; the scene's "
                         f"equation of state is {scene.eos.name!r}: use solver='wcsph'")
    if scene.neighbour_skin > 0:
        raise InputError(f"scene {scene.name!r}: solver='dfsph' builds its own pair list every step; set "
                         "neighbour_skin = 0 (--neighbour-skin 0)")
