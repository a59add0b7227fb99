"""Command line: ``python -m taisph ...`` (:mod:`taisph.cli.main`); the seed's
``run``/``export`` commands are in :mod:`taisph.cli.dat`."""
