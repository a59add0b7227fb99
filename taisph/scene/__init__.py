"""What to simulate: the :class:`Scene` data model (:mod:`.model`), the names of the
numerical choices (:mod:`.names`), the ranges of case parameters (:mod:`.parameters`),
the standard water physics the cases and scene files share (:mod:`.water`), the gas
terms (:mod:`.gas`), the built-in cases and shipped scene files (:mod:`.catalogue`), and a
scene as plain data for checkpoints (:mod:`.serialize`).
"""

from .model import Gas, Material, Scene

__all__ = ["Scene", "Material", "Gas"]
