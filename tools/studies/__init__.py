"""Studies whose results docs/ quotes: ``python -m tools.studies.NAME`` from the repository root."""
