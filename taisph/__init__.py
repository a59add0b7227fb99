"""taisph: smoothed particle hydrodynamics on Taichi.

    import taisph
    scene = taisph.cases.dam_break(dx=0.02)
    sim = taisph.Simulation(scene)
    sim.run(1.0, frames=20, out="out/dam_break")
"""

from . import messages  # noqa: F401 -- first, before anything imports taichi: its banner off stdout
from . import geometry
from .engine.layout import FLUID, WALL
from .scene import catalogue
from .scene.model import Gas, Material, Scene
from .run.simulation import RunSummary, Simulation

__version__ = "0.1.0"


cases = catalogue.load_cases()


def __getattr__(name):
    """``taisph.sweep`` on first use: it imports Dask, which is slow to import and an
    optional dependency (``pip install 'taisph[sweep]'``)."""
    if name == "sweep":
        from .sweeps import sweep

        return sweep
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["Simulation", "Scene", "Material", "Gas", "RunSummary", "cases", "FLUID", "WALL"]
