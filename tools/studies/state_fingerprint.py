"""A fingerprint of a case's state after N deterministic steps, to show that a change
of the code's structure changes no result.

    python -m tools.studies.state_fingerprint dam_break --steps 300 --set dx=0.04
    git checkout OTHER && python -m tools.studies.state_fingerprint dam_break --steps 300 --set dx=0.04

Runs the case (``--set NAME=VALUE`` as on the command line) with
``deterministic=True`` (serial cell sort: bit-reproducible), takes `--steps` steps and
prints the SHA-256 of the positions, velocities, densities and pressures (in
particle-id order, as float64 bytes) and of the clock. Equal digests mean bit-for-bit
equal states. Uses only the public API (``taisph.cases``, ``taisph.Simulation``), so
it runs on older commits too; on a commit from before tools/studies/ existed, run a copy
of this file kept outside the repository (``python /tmp/state_fingerprint.py ...``: it
imports nothing from tools/).
"""

import argparse
import hashlib

import numpy as np

import taisph


def parse(value: str):
    for convert in (int, float):
        try:
            return convert(value)
        except ValueError:
            pass
    return {"true": True, "false": False, "none": None}.get(value.lower(), value)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m tools.studies.state_fingerprint",
                                description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("case")
    p.add_argument("--steps", type=int, default=300)
    p.add_argument("--set", nargs="*", default=[], metavar="NAME=VALUE")
    p.add_argument("--precision", choices=["f32", "f64"], default="f64")
    args = p.parse_args(argv)
    params = dict((k, parse(v)) for k, v in (item.split("=", 1) for item in args.set))
    sim = taisph.Simulation(taisph.cases.CASES[args.case](**params), precision=args.precision, deterministic=True)
    sim.step(args.steps)
    digest = hashlib.sha256()
    for array in (sim.positions(), sim.velocities(), sim.density(), sim.pressure(), np.array([sim.time])):
        digest.update(np.ascontiguousarray(array, dtype=np.float64).tobytes())
    print(f"{args.case} {args.set} {args.precision}: {sim.steps} steps to t = {sim.time!r} s, "
          f"state sha256 {digest.hexdigest()[:16]}")


if __name__ == "__main__":
    main()
