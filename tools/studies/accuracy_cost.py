"""Work-precision study: what each choice buys in accuracy and costs in wall time.

    python -m tools.studies.accuracy_cost                  # full study (< 30 min on 2 cores), writes docs/accuracy/
    python -m tools.studies.accuracy_cost --quick --out /tmp/study   # CI: dam_break and poiseuille, small sizes
    python -m tools.studies.accuracy_cost --cases poiseuille couette --out /tmp/study
    python -m tools.studies.accuracy_cost --cases dam_break hydrostatic_tank couette --only DFSPH "WCSPH default" --out docs/accuracy/dfsph
    python -m tools.studies.accuracy_cost --workers 2                  # two runs at a time on this machine
    python -m tools.studies.accuracy_cost --scheduler tcp://host:8786   # spread over a Dask cluster (docs/sweeps.md)

The study itself (cases, configurations, resolutions, the CSV, table and plots it
writes; its runs are tasks of taisph's sweeps on Dask) is
:mod:`taisph.validation.accuracy_cost`; this is its command line.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the repository

from taisph.validation import accuracy_cost  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.accuracy_cost",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true", help="CI mode: dam_break and poiseuille, 2 configurations, small sizes")
    p.add_argument("--cases", nargs="+", choices=list(accuracy_cost.STUDY),
                   help="cases to run (default: all; --quick: dam_break, poiseuille)")
    p.add_argument("--out", default=str(ROOT / "docs" / "accuracy"), help="output folder (default docs/accuracy)")
    p.add_argument("--repeat", type=int, default=1, help="runs per point; the median wall time is reported")
    p.add_argument("--threads", type=int, default=None,
                   help="Taichi CPU threads per run (default: cores / workers; 1 with --scheduler)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=1,
                       help="runs at a time, each in a worker process of a local Dask cluster (default 1)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on an existing Dask cluster (dask scheduler / dask worker), e.g. tcp://host:8786")
    p.add_argument("--only", nargs="+", metavar="WORD",
                   help="only the configurations whose label contains one of these words (e.g. DFSPH 'WCSPH default')")
    args = p.parse_args(argv)

    command = ("python -m tools.studies.accuracy_cost"
               + (" " + " ".join(argv if argv is not None else sys.argv[1:])).rstrip())
    return accuracy_cost.run_study(args.out, cases=args.cases, quick=args.quick, repeat=args.repeat, command=command,
                                   workers=args.workers, scheduler=args.scheduler, threads=args.threads,
                                   only=args.only)


if __name__ == "__main__":
    main()
