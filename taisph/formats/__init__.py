"""Files that describe a scene: TOML scene files (:mod:`.scenefile` reads and checks
them, :mod:`.scenefile_build` builds the :class:`taisph.Scene`), and the seed's text
files (:mod:`.dat` reads and writes them, :mod:`.seed` turns them into a scene and a
scene back into them)."""
