"""Render frames of a taisph output folder to a PNG (needs matplotlib: pip install .[plot]).

    python -m tools.plots.render out/dam_break --times 0 0.25 0.5 1.0 --color pressure -o docs/dam_break.png

Reads the .pvd index and the .vtu frames with meshio, picks the frames nearest to the
requested times, and draws particles (2D: x-y; 3D: x-y projection) coloured by a
point array (vectors by their length), with the walls in grey and moving or floating
bodies in dark grey.
"""

import argparse
from pathlib import Path

import meshio
import numpy as np

from taisph.run.vtk import read_pvd


def _magnitude(values):
    """A point array as one number per point: itself, or the length of a vector."""
    values = np.asarray(values)
    return values if values.ndim == 1 else np.linalg.norm(values.reshape(len(values), -1), axis=1)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.plots.render",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folder", type=Path)
    p.add_argument("--times", type=float, nargs="+", help="times to show (default: 4 evenly spaced frames)")
    p.add_argument("--color", default="pressure", help="point array to colour by (default pressure)")
    p.add_argument("--title", default=None)
    p.add_argument("-o", "--output", type=Path, required=True)
    args = p.parse_args(argv)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pvd = next(args.folder.glob("*.pvd"))
    entries = read_pvd(pvd)
    frames = [(t, f) for t, part, f in entries if part == 0]
    walls = sorted({f for _, part, f in entries if part == 1})
    bodies = {t: f for t, part, f in entries if part == 2}  # moving and floating bodies, every frame
    times = args.times or [frames[int(k)][0] for k in np.linspace(0, len(frames) - 1, 4)]
    chosen = [min(frames, key=lambda e: abs(e[0] - t)) for t in times]
    wall_points = meshio.read(args.folder / walls[0]).points if walls else None
    meshes = [meshio.read(args.folder / f) for _, f in chosen]
    values = np.concatenate([_magnitude(m.point_data[args.color]) for m in meshes])
    vmin, vmax = np.percentile(values, [1, 99])
    fig, axes = plt.subplots(1, len(chosen), figsize=(4 * len(chosen), 4), squeeze=False, constrained_layout=True)
    for ax, (t, _), mesh in zip(axes[0], chosen, meshes):
        x = mesh.points
        c = _magnitude(mesh.point_data[args.color])
        if wall_points is not None:
            ax.scatter(wall_points[:, 0], wall_points[:, 1], s=0.5, c="0.6", linewidths=0)
        if t in bodies:
            b = meshio.read(args.folder / bodies[t]).points
            ax.scatter(b[:, 0], b[:, 1], s=0.8, c="0.25", linewidths=0)
        sc = ax.scatter(x[:, 0], x[:, 1], s=1.5, c=c, cmap="viridis", vmin=vmin, vmax=vmax, linewidths=0)
        ax.set_aspect("equal")
        ax.set_title(f"t = {t:.3g} s")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(sc, ax=axes[0].tolist(), shrink=0.8, label=args.color)
    if args.title:
        fig.suptitle(args.title)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
