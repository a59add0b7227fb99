"""Scripts around taisph, not part of the installed package: run them from the
repository root as modules, e.g. ``python -m tools.benchmarks.bench --help``.

benchmarks/  throughput and cost (the engine against a hand-fused loop, bare loops)
studies/     accuracy, stability and validation studies that write docs/ tables
peers/       other SPH codes (PySPH, SPlisHSPlasH) run on taisph's dam break
plots/       figures from a run's output
"""
