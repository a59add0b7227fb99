"""``python -m taisph plot OUT``: draw a run's probes against time (:mod:`taisph.probes.plot`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..messages import InputError
from .parser import Parser

HELP = """\
Draw a run's probes (OUT/probes.csv) against time into OUT/probes.png: one axis per
quantity and unit (pressure in Pa, surface elevation in m, force in N, flow rate in m^2/s
in 2D or m^3/s in 3D, a body's position, orientation, velocity, angular velocity and
force), as the sidecar OUT/probes.json records them (docs/probes.md). A dry pressure probe
(nan) is a gap in its line.

examples:
  python -m taisph plot out/dam_break_probes_2d
  python -m taisph plot out/cylinder/probes.csv --only p_front,p_back --out front_back.png

Needs matplotlib: pip install "taisph[plot]" (from taisph's folder: pip install ".[plot]")."""

MISSING = ('plot needs matplotlib, which is not installed: pip install "taisph[plot]" (in taisph\'s folder: '
           'pip install ".[plot]"), or pip install matplotlib')


def build_parser() -> Parser:
    parser = Parser(prog="python -m taisph plot", usage="python -m taisph plot OUT [--out FILE] [--only NAMES]",
                    description=HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", type=Path, metavar="OUT", help="a run's output folder (with probes.csv), or the CSV")
    parser.add_argument("--out", "-o", type=Path, metavar="FILE",
                        help="the image to write (default: probes.png beside probes.csv; .png, .pdf, .svg)")
    parser.add_argument("--only", metavar="NAMES", help="comma-separated probe (or column) names to draw")
    return parser


def main(argv=None) -> int:
    """Returns the exit code: 0 drawn, 2 refused (no such folder or CSV, a name --only does
    not know, no matplotlib), with one line on stderr."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as done:  # --help, printed
        return done.code or 0
    except InputError as err:
        print(f"taisph: error: {err}", file=sys.stderr)
        return 2
    try:
        return plot(args)
    except InputError as err:
        print(f"taisph: error: {err}", file=sys.stderr)
        return 2


def plot(args) -> int:
    try:
        import matplotlib  # noqa: F401  (the plot extra)
    except ImportError:
        raise InputError(MISSING) from None
    from ..probes.plot import csv_of, figure

    path = csv_of(args.run)  # (refused before anything is drawn)
    image = args.out or path.with_suffix(".png")
    if image.parent and not image.parent.is_dir():
        raise InputError(f"--out {image}: no folder {image.parent}")
    fig, axes = figure(path, [n for n in args.only.split(",") if n] if args.only else None)
    try:
        fig.savefig(image, dpi=110)
    except (OSError, ValueError) as err:
        raise InputError(f"--out {image}: cannot write it ({err})") from None
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)
    print(f"wrote {image}: {', '.join(a.label for a in axes)}")
    return 0
