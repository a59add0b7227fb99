"""taisph: smoothed particle hydrodynamics on Taichi.

    import taisph
    scene = taisph.cases.dam_break(dx=0.02)
    sim = taisph.Simulation(scene)
    sim.run(1.0, frames=20, out="out/dam_break")
"""

import importlib.util as _util
import sys as _sys
from pathlib import Path as _Path

from . import geometry
from .engine.layout import FLUID, WALL
from .scene import Gas, Material, Scene
from .simulation import RunSummary, Simulation

__version__ = "0.1.0"


def _load_cases():
    """Import the built-in cases as ``taisph.cases``.

    An installed taisph has them as a subpackage. A source checkout (``python -m
    taisph`` from the repository root) keeps them in ``cases/`` beside ``taisph/``.
    """
    try:
        from . import cases  # noqa: F401  (installed)
    except ImportError:
        src = _Path(__file__).resolve().parent.parent / "cases"
        spec = _util.spec_from_file_location(
            f"{__name__}.cases", src / "__init__.py", submodule_search_locations=[str(src)]
        )
        if spec is None:
            raise ImportError(f"taisph's cases are neither installed nor in {src}") from None
        module = _util.module_from_spec(spec)
        _sys.modules[spec.name] = module
        spec.loader.exec_module(module)
    return _sys.modules[f"{__name__}.cases"]


cases = _load_cases()


def __getattr__(name):
    """``taisph.sweep`` on first use: it imports Dask, which is slow to import and an
    optional dependency (``pip install 'taisph[sweep]'``)."""
    if name == "sweep":
        from .sweeps import sweep

        return sweep
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["Simulation", "Scene", "Material", "Gas", "RunSummary", "cases", "FLUID", "WALL"]
