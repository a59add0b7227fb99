"""Time taisph.geometry.volume_points and surface_points on a sphere mesh.

    python -m tools.benchmarks.bench_mesh_fill [--points 1e6] [--subdivisions 5]

Fills an icosphere (20 * 4**subdivisions triangles, default 20480) with about
`points` lattice points, read from a binary STL file, and reports the time of each
step (best of 3) and the volume error N dx^3 / V_mesh - 1. docs/scenes.md quotes it.
"""

import argparse
import math
import tempfile
import time
from pathlib import Path

import meshio

from taisph.geometry import surface_points, volume_points
from taisph.geometry.mesh import icosphere, load_surface


def best_of(n, func):
    times = []
    for _ in range(n):
        start = time.perf_counter()
        out = func()
        times.append(time.perf_counter() - start)
    return min(times), out


def main():
    parser = argparse.ArgumentParser(prog="python -m tools.benchmarks.bench_mesh_fill",
                                     description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--points", type=float, default=1e6, help="points to fill (about)")
    parser.add_argument("--subdivisions", type=int, default=5, help="icosphere subdivisions")
    args = parser.parse_args()
    vertices, faces = icosphere(1.0, args.subdivisions)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "sphere.stl"
        meshio.write(path, meshio.Mesh(vertices, [("triangle", faces)]), binary=True)
        t_read, surface = best_of(3, lambda: load_surface(path))
    dx = (surface.measure / args.points) ** (1 / 3)
    t_fill, points = best_of(3, lambda: volume_points(surface, dx))
    layers = 3
    t_shell, shell = best_of(3, lambda: volume_points(surface, dx, depth=layers * dx))
    t_surface, on_surface = best_of(3, lambda: surface_points(surface, dx / 2))
    error = len(points) * dx**3 / surface.measure - 1
    print(f"sphere R = 1, {len(faces)} triangles (binary STL), dx = {dx:.4g} (R/dx = {1 / dx:.0f})")
    print(f"  read and check the mesh:       {t_read:7.3f} s")
    print(f"  volume_points:                 {t_fill:7.3f} s  {len(points):>9} points "
          f"({len(points) / t_fill / 1e6:.1f} M/s), N dx^3 / V_mesh - 1 = {error:+.2e}")
    print(f"  volume_points, depth {layers} dx:     {t_shell:7.3f} s  {len(shell):>9} points")
    print(f"  surface_points, spacing dx/2:  {t_surface:7.3f} s  {len(on_surface):>9} points")
    print(f"  (sphere volume 4/3 pi = {4 / 3 * math.pi:.6f}, mesh volume {surface.measure:.6f})")


if __name__ == "__main__":
    main()
