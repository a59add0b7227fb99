"""Benchmarks: ``python -m tools.benchmarks.NAME`` from the repository root."""
