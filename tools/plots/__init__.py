"""Figures: ``python -m tools.plots.NAME`` from the repository root (needs matplotlib)."""
