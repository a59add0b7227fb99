"""Plot a run's probes (OUT/probes.csv) against time; with --buchner or --kleefsman, over
the experiments. Without them it is ``python -m taisph plot`` (taisph/cli/plot.py, which
ships with the package and runs from any folder: one axis per quantity and unit).

    python -m tools.plots.plot_probes OUT                     # OUT/probes.png (= python -m taisph plot OUT)
    python -m tools.plots.plot_probes OUT --buchner           # P1/P2 over Buchner's (2002) measurements
    python -m tools.plots.plot_probes OUT --kleefsman         # SPHERIC test 2: P1-P4, H2, H4 over the experiment
    python -m tools.plots.plot_probes OUT -o fig.png --only P1,P2

With --buchner (the 2D dam break of cases/dam_break_probes_2d.toml) pressure
probes named P1 and P2 are drawn as p / (rho0 g H) against t sqrt(g/H), H = 0.6 m,
over the experiment (taisph/validation/references/data/buchner2002_*), with the impact
time and mean absolute error of taisph.validation.buchner in the legend. A probe that
read no value (dry) is a gap in its line. With --kleefsman (the 3D dam break of
cases/dam_break_obstacle_3d.toml) the pressures P1-P4 and heights H2, H4 are drawn in
rho g H and H (H = 0.55 m) against t over the SPHERIC test 2 experiment, with the metrics of
taisph.validation.kleefsman in the legend. The other probes follow, an axis per quantity
and unit (taisph.probes.plot). Needs matplotlib (pip install ".[plot]").
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from taisph.cli.plot import MISSING, main as plot_main
from taisph.messages import InputError


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.plots.plot_probes", description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__,
                                     allow_abbrev=False)
    parser.add_argument("out", type=Path, help="a run's output folder (with probes.csv), or the CSV itself")
    parser.add_argument("-o", "--output", type=Path, help="image to write (default: OUT/probes.png)")
    parser.add_argument("--buchner", action="store_true", help="P1, P2 over Buchner's 2002 dam-break pressures")
    parser.add_argument("--kleefsman", action="store_true", help="P1-P4, H2, H4 over the SPHERIC test 2 experiment")
    parser.add_argument("--only", help="comma-separated probe names to plot")
    args = parser.parse_args(argv)
    if not (args.buchner or args.kleefsman):
        return plot_main([str(args.out), *(["--out", str(args.output)] if args.output else []),
                          *(["--only", args.only] if args.only else [])])
    try:
        return compare(args)
    except InputError as err:
        print(f"plot_probes: {err}", file=sys.stderr)
        return 2


def compare(args) -> int:
    """The experiments' panels, then an axis per quantity and unit for the other probes."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise InputError(MISSING) from None
    from taisph.probes import read_units
    from taisph.probes.plot import axes_of, csv_of, draw, guessed_units, read_table

    csv_path = csv_of(args.out)
    header, values, sampled = read_table(csv_path)
    only = set(args.only.split(",")) if args.only else None
    units = read_units(csv_path) or guessed_units(header, values)
    data = {c: values[:, k] for k, c in enumerate(header)}
    t = data["time"]
    if args.buchner:
        from taisph.validation.buchner import PROBES

        panels = [("buchner", [c for c in header if c in PROBES and (not only or c in only)])]
    else:
        from taisph.validation.kleefsman import HEIGHT_GAUGES, PRESSURE_SENSORS

        panels = [("kleefsman", [c for c in header if c in names and (not only or c in only)])
                  for names in (PRESSURE_SENSORS, HEIGHT_GAUGES)]
    panels = [(kind, cols) for kind, cols in panels if cols]
    shown = {c for _, cols in panels for c in cols}
    rest = axes_of([c for c in header if c not in shown], units, only)
    heights = [4.0] * len(panels) + [2.6] * len(rest)
    if not heights:
        raise InputError(f"{csv_path}: none of {args.only} among its probes ({', '.join(header[1:])})")
    fig, axes = plt.subplots(len(heights), 1, figsize=(9, sum(heights)), squeeze=False,
                             gridspec_kw={"height_ratios": heights})
    for ax, (kind, cols) in zip(axes[:, 0], panels):
        if kind == "buchner":
            _buchner(ax, t, data, cols)
        else:
            _kleefsman(ax, t, data, cols, {c: sampled[:, header.index(c)] for c in cols})
    for ax, spec in zip(axes[len(panels) :, 0], rest):
        draw(ax, spec, header, values, sampled)
        ax.set_xlabel("t (s)")
    fig.suptitle(str(csv_path), fontsize=9)
    fig.tight_layout()
    image = args.output or csv_path.with_suffix(".png")
    fig.savefig(image, dpi=110)
    print(f"wrote {image}")
    return 0


def _buchner(ax, t, data, cols):
    """P1, P2 (and P1_point, P2_point) over the experiment, with their metrics; the
    impact time only for P1's (P2 stays dry until the run-up: no impact to time)."""
    from taisph.validation import buchner

    scale = np.sqrt(buchner.G / buchner.H)
    for c in cols:
        sensor = buchner.PROBES[c]
        T, P = t * scale, data[c] / (buchner.RHO0 * buchner.G * buchner.H)
        m = buchner.compare(T, P, sensor)
        impact = f"impact T = {m['impact_T']:.3f} ({100 * m['impact_error']:+.1f} %), " if sensor == "P1" else ""
        ax.plot(T, P, lw=0.7 if c == sensor else 0.5, alpha=1.0 if c == sensor else 0.6,
                label=f"{c} taisph: {impact}MAE = {m['mae']:.3f}")
        print(f"{c}: {impact}MAE over T in [{m['window'][0]:g}, {m['window'][1]:.2f}] = {m['mae']:.4f} rho g H")
    for sensor in sorted({buchner.PROBES[c] for c in cols}):
        T_ref, P_ref = buchner.reference(sensor)
        impact = f": impact T = {buchner.impact_time(T_ref, P_ref):.3f}" if sensor == "P1" else ""
        ax.plot(T_ref, P_ref, "ko-" if sensor == "P1" else "k^-", ms=2.5, lw=1,
                label=f"{sensor} Buchner (2002){impact}")
    ax.axvspan(*buchner.WINDOW, color="0.93", zorder=0)
    ax.set_xlabel("t sqrt(g/H)")
    ax.set_ylabel("p / (rho g H)")
    ax.set_xlim(1.5, 7.5)
    ax.legend(fontsize=6.5, loc="lower right", framealpha=0.8)
    ax.grid(alpha=0.3)


def _kleefsman(ax, t, data, cols, sampled):
    """Pressures (or heights) over the SPHERIC test 2 experiment, with their metrics
    (over each probe's own samples, `sampled`: {column: rows}, a dry one counting as 0,
    as kleefsman.run has them)."""
    from taisph.validation import kleefsman

    ref = kleefsman.reference()
    pressure = cols[0].startswith("P")
    scale = kleefsman.RHO0 * kleefsman.G * kleefsman.H if pressure else kleefsman.H
    colours = plt_colours()
    for k, c in enumerate(cols):
        taken = sampled[c]
        if pressure:
            m = kleefsman.compare_pressure(t[taken], data[c][taken], c)
            label = (f"{c} taisph: peak {m['peak']:.2f} ({m['peak_ref']:.2f}), impact "
                     f"{m['impact_error'] * 1e3:+.0f} ms, MAE {m['mae']:.3f}")
        else:
            m = kleefsman.compare_height(t[taken], data[c][taken], c)
            label = f"{c} taisph: MAE {m['mae']:.3f}"
        print(f"{c}: {label.split(': ', 1)[1]}")
        ax.plot(t[taken], np.nan_to_num(data[c][taken]) / scale, lw=0.8, color=colours[k], label=label)
        ax.plot(ref["t"], ref[c] / scale, lw=0.6, ls="--", color=colours[k], alpha=0.8, label=f"{c} experiment")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("p / (rho g H)" if pressure else "h / H")
    ax.set_xlim(0, float(ref["t"][-1]))
    ax.legend(fontsize=6.5, loc="upper right", framealpha=0.8, ncol=2)
    ax.grid(alpha=0.3)


def plt_colours():
    import matplotlib.pyplot as plt

    return plt.rcParams["axes.prop_cycle"].by_key()["color"]


if __name__ == "__main__":
    sys.exit(main())
