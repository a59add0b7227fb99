"""Points for scenes: lattices, tank walls, segments and balls (:mod:`.shapes`), and
points on and inside closed surfaces read from mesh files (:mod:`.mesh` reads and
checks them, :mod:`.fill` samples them).

    from taisph.geometry import lattice, box_walls
"""

from .shapes import (ball, box_walls, container_layers, extrude, inside_triangle, lattice, polyline, segment,
                     side_walls, support_layers, wall_layers)
from .fill import surface_points, volume_points

__all__ = ["ball", "box_walls", "container_layers", "extrude", "inside_triangle", "lattice", "polyline", "segment",
           "side_walls", "support_layers", "wall_layers", "surface_points", "volume_points"]
