"""Other SPH codes on taisph's dam break: ``python -m tools.peers.NAME`` from the repository root.
pysph_dam_break and splishsplash_dam_break run in the peer code's own Python and import
nothing from taisph or tools."""
