"""Plot a run's probes (OUT/probes.csv) against time: one panel per probe kind.

    python -m tools.plots.plot_probes OUT                     # OUT/probes.png
    python -m tools.plots.plot_probes OUT --buchner           # P1/P2 over Buchner's (2002) measurements
    python -m tools.plots.plot_probes OUT --kleefsman         # SPHERIC test 2: P1-P4, H2, H4 over the experiment
    python -m tools.plots.plot_probes OUT -o fig.png --only P1,P2

Pressures are in Pa, elevations in m, forces in N (one line per component), against
t in s. With --buchner (the 2D dam break of cases/dam_break_probes_2d.toml) pressure
probes named P1 and P2 are drawn as p / (rho0 g H) against t sqrt(g/H), H = 0.6 m,
over the experiment (taisph/validation/references/data/buchner2002_*), with the impact
time and mean absolute error of taisph.validation.buchner in the legend. A probe that
read no value (dry) is a gap in its line. With --kleefsman (the 3D dam break of
cases/dam_break_obstacle_3d.toml) the pressures P1-P4 and heights H2, H4 are drawn in
rho g H and H (H = 0.55 m) against t over the SPHERIC test 2 experiment, with the metrics of
taisph.validation.kleefsman in the legend. Needs matplotlib (pip install ".[plot]").
"""

import argparse
import sys
from pathlib import Path

import numpy as np

from taisph.probes import read_csv


# a body probe's columns (taisph.probes.BODY_COLUMNS) in panels by unit: the panel's label, the columns' endings
BODY_PANELS = (("position (m)", ("x", "y", "z")), ("orientation", ("angle", "qw", "qx", "qy", "qz")),
               ("velocity (m/s, rad/s)", ("vx", "vy", "vz", "omega", "wx", "wy", "wz")),
               ("force (N)", ("fx", "fy", "fz")))


def kinds(columns):
    """Group CSV columns by what they measure: a body probe's (name_angle or name_qw
    among them) by body into :data:`BODY_PANELS`; forces (name_x, name_y(, name_z)) by
    name; the rest by unit as the header cannot tell pressure from elevation: a column
    whose values stay below 100 is taken for an elevation (m)."""
    forces, scalars = {}, []
    names = list(columns)
    bodies = {c.rpartition("_")[0] for c in names if c.endswith(("_angle", "_qw"))}
    body_panels = [(f"{b} {label}", [f"{b}_{e}" for e in endings if f"{b}_{e}" in names])
                   for b in sorted(bodies) for label, endings in BODY_PANELS]
    taken = {c for _, cols in body_panels for c in cols}
    for c in names:
        if c in taken:
            continue
        base, _, axis = c.rpartition("_")
        if axis in ("x", "y", "z") and f"{base}_x" in names and f"{base}_y" in names:
            forces.setdefault(base, []).append(c)
        else:
            scalars.append(c)
    return forces, scalars, body_panels


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.plots.plot_probes", description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("out", type=Path, help="a run's output folder (with probes.csv), or the CSV itself")
    parser.add_argument("-o", "--output", type=Path, help="image to write (default: OUT/probes.png)")
    parser.add_argument("--buchner", action="store_true", help="P1, P2 over Buchner's 2002 dam-break pressures")
    parser.add_argument("--kleefsman", action="store_true", help="P1-P4, H2, H4 over the SPHERIC test 2 experiment")
    parser.add_argument("--only", help="comma-separated probe names to plot")
    args = parser.parse_args(argv)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_probes: needs matplotlib (pip install '.[plot]')", file=sys.stderr)
        return 2
    csv_path = args.out if args.out.suffix == ".csv" else args.out / "probes.csv"
    if not csv_path.is_file():
        print(f"plot_probes: {csv_path}: no such file (run a scene file with [[probes]])", file=sys.stderr)
        return 2
    data = read_csv(csv_path)
    t = data.pop("time")
    if args.only:
        wanted = set(args.only.split(","))
        data = {k: v for k, v in data.items() if k in wanted or k.rpartition("_")[0] in wanted}
        if not data:
            print(f"plot_probes: none of {args.only} in {csv_path} (columns: {', '.join(read_csv(csv_path))})",
                  file=sys.stderr)
            return 2
    forces, scalars, body_panels = kinds(data)
    if args.buchner:
        from taisph.validation.buchner import PROBES

        panels = [("buchner", [c for c in scalars if c in PROBES])]
        scalars = [c for c in scalars if c not in PROBES]
    elif args.kleefsman:
        from taisph.validation.kleefsman import HEIGHT_GAUGES, PRESSURE_SENSORS

        panels = [("kleefsman", [c for c in scalars if c in PRESSURE_SENSORS]),
                  ("kleefsman", [c for c in scalars if c in HEIGHT_GAUGES])]
        scalars = [c for c in scalars if c not in PRESSURE_SENSORS + HEIGHT_GAUGES]
    else:
        panels = []
    metres = [c for c in scalars if np.nanmax(np.abs(data[c]), initial=0.0) < 100.0]
    pascals = [c for c in scalars if c not in metres]
    panels += [("pressure", pascals), ("elevation", metres)] + [("force", [name]) for name in forces] + body_panels
    panels = [(kind, cols) for kind, cols in panels if cols]
    heights = [4.0 if kind in ("buchner", "kleefsman") else 2.8 for kind, _ in panels]
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, sum(heights)), squeeze=False,
                             gridspec_kw={"height_ratios": heights})
    for ax, (kind, cols) in zip(axes[:, 0], panels):
        if kind == "buchner":
            _buchner(ax, t, data, cols)
            continue
        if kind == "kleefsman":
            _kleefsman(ax, t, data, cols, csv_path)
            continue
        for c in cols:
            for column in forces.get(c, [c]):
                taken = ~np.isnan(data[column]) | (kind == "pressure")  # keep gaps where a point is dry
                ax.plot(t[taken], data[column][taken], lw=0.8, label=column)
        ax.set_ylabel({"pressure": "p (Pa)", "elevation": "surface (m)", "force": "force (N)"}.get(kind, kind))
        ax.set_xlabel("t (s)")
        ax.legend(fontsize=8, loc="best")
        ax.grid(alpha=0.3)
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


def _kleefsman(ax, t, data, cols, csv_path):
    """Pressures (or heights) over the SPHERIC test 2 experiment, with their metrics
    (over each probe's own samples, a dry one counting as 0, as kleefsman.run has them)."""
    import csv

    from taisph.validation import kleefsman

    with open(csv_path, newline="") as f:
        rows = list(csv.reader(f))
    sampled = {c: np.array([r[rows[0].index(c)] != "" for r in rows[1:]]) for c in cols}

    ref = kleefsman.reference()
    pressure = cols[0].startswith("P")
    scale = kleefsman.RHO0 * kleefsman.G * kleefsman.H if pressure else kleefsman.H
    colours = plt_colours()
    for k, c in enumerate(cols):
        taken = sampled[c]
        if pressure:
            m = kleefsman.compare_pressure(t[taken], data[c][taken], c)
            label = f"{c} taisph: peak {m['peak']:.2f} ({m['peak_ref']:.2f}), impact {m['impact_error'] * 1e3:+.0f} ms, MAE {m['mae']:.3f}"
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
