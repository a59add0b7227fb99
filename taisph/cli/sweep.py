"""``python -m taisph sweep CASE --vary NAME=v1,v2,... --out DIR``: a parameter sweep
on a Dask cluster (:func:`taisph.sweeps.sweep`; docs/sweeps.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..messages import InputError
from .case import CONTROLS
from .parser import Parser, UsageError

DESCRIPTION = ("python -m taisph sweep CASE --vary NAME=v1,v2,... --out DIR: a parameter sweep on a Dask "
               "cluster, one run per combination of the values (docs/sweeps.md).")

# the help's closing paragraphs (filled to the terminal's width, the lists from the code), then its examples
PARAGRAPHS = (
    "Each combination of the --vary values is one run in a Dask worker process: by default a LocalCluster of "
    "--workers processes started here (one per core, each run using its share of the cores), or an existing "
    "cluster with --scheduler tcp://host:port (started with `dask scheduler` and `dask worker tcp://host:port "
    "--nworkers N --nthreads 1`).",
    "Names: any case parameter (CASE --help; a scene file's: {scene_names}, its values the defaults), the run "
    "settings {settings} and, for validation runs, the validation's keywords (dt_factor, T_end, samples, ...).",
    "A case with a reference ({validations}) runs its validation: the error column is measured against the "
    "reference. --no-validate makes plain runs to the scene's t_end instead.",
    "DIR/sweep.csv and DIR/sweep.md get a row as each run finishes; run again with the same options to resume "
    "(done combinations are skipped). A sweep that stops before any run finished (no cluster, Ctrl-C) leaves no "
    "table; a folder whose runs all failed takes another sweep.",
)
EXAMPLES = """\
examples:
  python -m taisph sweep hydrostatic_tank --vary dx=0.1,0.05 --vary kernel=spline,wendland --t-end 0.5 --out sweeps/tank
  python -m taisph sweep dam_break --vary dx=0.1,0.05 --set T_end=1 --workers 2 --out sweeps/db
  python -m taisph sweep dam_break --no-validate --vary dt=1e-4,2e-3 --dx 0.1 --t-end 0.2 --out sweeps/dt
  python -m taisph sweep dam_break_probes_2d.toml --vary dx=0.04,0.02 --t-end 0.5 --out sweeps/scene
  python -m taisph sweep poiseuille --vary dx=1e-4,5e-5 --scheduler tcp://10.0.0.5:8786 --out sweeps/p"""


def _fill(text: str) -> str:
    """`text` wrapped between words to the terminal's width (as argparse wraps the options' help)."""
    import shutil
    import textwrap

    width = max(40, min(100, shutil.get_terminal_size().columns - 2))
    return textwrap.fill(text, width, break_long_words=False, break_on_hyphens=False)


def _epilog() -> str:
    """The help's closing paragraphs with the lists the code holds (the cases with a
    reference, the run settings, a scene file's parameters), then the examples."""
    from ..formats.scenefile import SWEEP_KEYS
    from ..scene import catalogue
    from ..sweeps.plan import SETTINGS
    from ..validation import VALIDATIONS

    references = [name for name in VALIDATIONS if name in catalogue.registry()]  # the cases among them
    lists = dict(validations=", ".join(references), settings=", ".join(SETTINGS), scene_names=", ".join(SWEEP_KEYS))
    return "\n\n".join([*(_fill(p.format(**lists)) for p in PARAGRAPHS), EXAMPLES])


def _this_case(case: str | None) -> dict:
    """``"; this case: VALUE"`` per option a case or scene file sets (its default scene's
    values, as ``CASE --help`` shows them), or "" each without a case or for one that
    does not build."""
    import collections

    from .case import _case_defaults

    if case is None:
        return collections.defaultdict(str)
    from ..sweeps import plan

    try:
        factory = plan.resolve_case(case)
        scene = factory()
        if getattr(factory, "courant", None) is not None:  # a scene file's Courant number (a control)
            scene.courant = factory.courant
    except Exception:  # an unknown case or a broken file: the general help
        return collections.defaultdict(str)
    return _case_defaults(scene)


def build_parser(case: str | None = None) -> Parser:
    """The sweep's options (a :class:`taisph.cli.parser.Parser`: bad usage raises
    UsageError, printed by :func:`main` with exit code 2); with `case` (``sweep CASE
    --help``), its help shows the values that case runs with."""
    from ..engine.dfsph.method import DFSPH_COURANT
    from ..scene import Scene
    from ..sweeps.plan import DEFAULT_PRECISION

    this = _this_case(case)
    parser = Parser(prog="python -m taisph sweep", description=_fill(DESCRIPTION), epilog=_epilog(),
                    formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", help="case name (python -m taisph list), or a scene file SCENE.toml")
    parser.add_argument("--vary", action="append", default=[], metavar="NAME=v1,v2,...",
                        help="values of one parameter or setting; repeatable: the runs are the product")
    g = parser.add_argument_group("every run (as for a single run: python -m taisph CASE --help)")
    g.add_argument("--dx", help=f"particle spacing (m); default: the case's{this['dx']}")
    g.add_argument("--t-end", help=f"simulated end time (s); default: the case's{this['t_end']}")
    g.add_argument("--frames", help="frames of each run (they fix the times steps land on; written only with "
                                    f"--frames-per-run); default: the case's{this['frames']}")
    g.add_argument("--integrator", help=f"time integrator; default: the case's{this['integrator']}")
    g.add_argument("--kernel", help=f"smoothing kernel; default: the case's{this['kernel']}")
    g.add_argument("--dt", help="fixed time step (s); default: adaptive")
    g.add_argument("--courant", help="Courant number of the adaptive step; default: the case's or scene file's "
                                     f"own (sweep CASE --help shows it), else {CONTROLS['courant']:g}; DFSPH "
                                     f"{DFSPH_COURANT:g}{this['courant']}")
    g.add_argument("--precision", help=f"f32 or f64 (default {DEFAULT_PRECISION})")
    g.add_argument("--neighbour-skin", help=f"neighbour list skin (default {Scene.neighbour_skin:g}: no lists)")
    g.add_argument("--max-density-error", help="guard: stop when |rho/rho0 - 1| exceeds this (default "
                                               f"{CONTROLS['max_density_error']:g})")
    g.add_argument("--deterministic", action="store_true", help="bit-for-bit reproducible runs")
    g.add_argument("--remove-escaped", action="store_true", help="remove particles that leave the domain")
    g.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="any case parameter; repeatable")
    g.add_argument("--no-validate", action="store_true",
                   help="plain runs to t_end even when the case has a reference (no error column)")
    _cluster_options(parser)
    return parser


def _cluster_options(parser) -> None:
    """The group "cluster and output"."""
    g = parser.add_argument_group("cluster and output")
    where = g.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="worker processes of the LocalCluster (default: one per core)")
    where.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask cluster, e.g. tcp://host:8786")
    g.add_argument("--threads", help="CPU threads per run (default: cores / workers; 1 on an existing cluster)")
    g.add_argument("--out", type=Path, required=True, help="folder of sweep.csv and sweep.md (and frames)")
    g.add_argument("--frames-per-run", action="store_true", help="write each run's frames to DIR/<run name>/")
    g.add_argument("--retry-failed", action="store_true", help="on resume, run the failed combinations again")
    g.add_argument("--no-progress", action="store_true", help="no progress bar")


def case_argument(argv) -> str | None:
    """The CASE of a sweep's command line (its first positional word: not an option, nor
    an option's value), or None: ``sweep CASE --help`` then shows that case's values."""
    parser = build_parser()
    takes_value = {o for a in parser._actions if a.option_strings and a.nargs != 0 for o in a.option_strings}
    words = iter(argv)
    for word in words:
        if word == "--":
            return next(words, None)
        if word.startswith("-"):
            if word in takes_value:
                next(words, None)
            continue
        return word
    return None


def fixed_values(args) -> dict:
    """The values every run shares: the options as text (parsed by the sweep against
    the case), ``--set`` of a case parameter parsed as the case command parses it
    (:func:`taisph.scene.catalogue.parse_setting`), ``--set`` of a run setting or validation
    keyword as text."""
    from ..scene import catalogue

    fixed = {}
    for option in ("dx", "t_end", "frames", "integrator", "kernel", "dt", "courant", "precision", "neighbour_skin",
                   "max_density_error", "threads"):
        if getattr(args, option) is not None:
            fixed[option] = getattr(args, option)
    for flag in ("deterministic", "remove_escaped"):
        if getattr(args, flag):
            fixed[flag] = True
    from ..sweeps import plan

    scene_file = plan.is_scene_file(args.case)
    parameters = plan.case_parameters(args.case)
    for item in args.set:
        name, sep, value = item.partition("=")
        name = name.strip().replace("-", "_")
        if not sep or not name:
            raise UsageError(f"--set expects NAME=VALUE, got {item!r}")
        if name in fixed:
            raise UsageError(f"{name} is given twice")
        known = name in parameters and not scene_file  # a scene file's are parsed by the sweep
        fixed[name] = catalogue.parse_setting(args.case, item)[1] if known else value.strip()
    return fixed


def main(argv) -> int:
    from ..sweeps import SweepError, plan, sweep

    try:
        args = build_parser(case_argument(argv) if {"-h", "--help"} & set(argv) else None).parse_args(argv)
        before = _table_runs(args.out, args.retry_failed)
        vary = plan.parse_vary(args.vary)
        fixed = fixed_values(args)
        rows = sweep(args.case, vary, out=args.out, workers=args.workers, scheduler=args.scheduler,
                     validate=False if args.no_validate else None, frames_per_run=args.frames_per_run,
                     retry_failed=args.retry_failed, progress=not args.no_progress, **fixed)
    except (SweepError, InputError) as err:  # refused input; anything else is a fault of taisph: a traceback
        print(f"taisph sweep: error: {err}", file=sys.stderr)
        return 2
    failed = sum(row["status"] != "ok" for row in rows)
    kept = sum(row["run"] in before for row in rows)
    print((args.out / "sweep.md").read_text(), end="")
    print(f"\n{len(rows)} runs: {len(rows) - failed} ok, {failed} failed"
          + (f" ({kept} already in the table, not run again)" if kept else "")
          + f"; table in {args.out / 'sweep.csv'}")
    return 0


def _table_runs(folder: Path, retry_failed: bool) -> set:
    """Names of the runs an earlier sweep into `folder` left in its table (that a
    rerun keeps: with --retry-failed, the ok ones only)."""
    import csv

    path = folder / "sweep.csv"
    if not path.exists():
        return set()
    with open(path, newline="") as f:
        return {row["run"] for row in csv.DictReader(f) if not retry_failed or row.get("status") == "ok"}
