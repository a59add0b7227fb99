"""The solvers: name -> method (:class:`taisph.engine.method.Method`), one folder each.

The assembly compiles the method of the scene's ``solver``; the time step composes its
controls from every method's; a new solver is its folder (``engine/<name>/``, its
``method.METHOD``) and one entry here.
"""

from .dfsph import method as dfsph
from .wcsph import method as wcsph
from ..scene.names import SOLVERS as NAMES  # the one list of the names (checked below)

METHODS = {method.name: method for method in (wcsph.METHOD, dfsph.METHOD)}
if tuple(METHODS) != NAMES:  # taisph/scene/names.py, in the same order
    raise ImportError(f"engine solvers {tuple(METHODS)} differ from taisph.scene.names.SOLVERS")


def of(scene):
    """The method of `scene`'s solver (``Scene.solver``; "wcsph" if it names none)."""
    name = getattr(scene, "solver", "wcsph")
    try:
        return METHODS[name]
    except KeyError:
        raise ValueError(f"unknown solver {name!r}; choose one of {', '.join(METHODS)}") from None
