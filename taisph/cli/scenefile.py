"""``python -m taisph SCENE.toml [options]``: run a scene file (:mod:`taisph.formats.scenefile`)
with the case options where they apply, and list the shipped scene files."""

from __future__ import annotations

import sys
from pathlib import Path

from ..formats.scenefile import load
from ..formats.scenefile_spec import SceneFileError, read, tomllib
from ..messages import InputError
from ..scene import catalogue
from .case import build_parser, command_line_probes, guarded, probe_folder, probe_notes, probe_writers, simulate
from .case_help import first_sentence, list_entry

EPILOG = """\
examples:
  python -m taisph dam_break_probes_2d.toml                 # a scene file shipped in cases/
  python -m taisph my_scene.toml --dx 0.01 --t-end 1 --out run1
  python -m taisph my_scene.toml --set physics.alpha=0.05 --checkpoint-every 5   # Ctrl-C, then:
  python -m taisph resume out/NAME/checkpoint
Open OUT/NAME.pvd in ParaView (File > Open, Apply) to see the time series; python -m taisph OUT
says how OUT was made (OUT/run.json)."""


def list_scene_files(out=None):
    """Print the scene files shipped in cases/ (for ``python -m taisph list``)."""
    out = sys.stdout if out is None else out
    files = catalogue.scene_files()
    if not files:
        return
    print("scene files (python -m taisph NAME.toml; copy one from cases/ to make your own):", file=out)
    width = max(len(f.name) for f in files)
    for f in files:
        try:
            spec = read(f)
            about = first_sentence(spec.description) if spec.description else spec.name
        except SceneFileError as err:
            about = f"(does not load: {err})"
        print(list_entry(f.name, width, about), file=out)


def _set_value(text: str):
    """A --set value as TOML (numbers, lists, true/false, "strings"), else the text."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def main(argv) -> int:
    """``python -m taisph SCENE.toml [options]``: the case options where they apply;
    ``--set KEY=VALUE`` sets any key of the file (``--set physics.alpha=0.05``). Returns
    the exit code (:func:`taisph.cli.case.guarded`; the options are checked under it too)."""
    return guarded(_main, argv)


def _main(argv) -> int:
    parser = build_parser(target_help="the scene file (a path, or the name of one shipped in cases/)")
    parser.usage = "python -m taisph SCENE.toml [options]"
    parser.description = ("Run a scene file (schema: docs/scenes.md). The options below replace the file's values "
                          "where they apply; --set KEY=VALUE sets any key of the file, as TOML: "
                          "--set physics.alpha=0.05, --set 'fluid[0].velocity=[1.0, 0.0]'.")
    parser.epilog = EPILOG
    args = parser.parse_args(argv)
    return run_file(catalogue.find_scene_file(args.case[0]), args)


def run_file(path: Path, args) -> int:
    """Run the scene file `path` with the case options `args`. Its probes go to OUT/probes.csv whatever the
    frames (also with --no-output, which writes no frames); ``frames = 0`` writes the initial frame only."""
    options = ("dx", "t_end", "frames", "integrator", "kernel", "dt", "courant", "solver")
    overrides = {k: getattr(args, k) for k in options if getattr(args, k) is not None}
    for item in args.set:
        if "=" not in item:
            raise InputError(f"--set expects KEY=VALUE, got {item!r}")
        key, text = item.split("=", 1)
        overrides[key.strip()] = _set_value(text.strip())
    scene, settings = load(path, overrides)
    notes = list(settings.notes)  # each wall group: its kind, particles, the fluid an obstacle removed
    probes = list(settings.probes) + command_line_probes(args, scene, settings.wall_groups)
    names = [p.name for p in probes]
    for name in names:
        if names.count(name) > 1:
            raise InputError(f"--probe: two probes named {name!r} (the scene file's and --probe's names must differ)")
    folder = probe_folder(scene, args)  # OUT, also with --no-output (which writes no frames)
    writers = probe_writers(probes, settings.wall_groups, folder)
    notes += probe_notes(probes, folder)
    try:
        return simulate(scene, args, t_end=settings.t_end, frames=settings.frames, notes=notes, writers=writers,
                        controls={**settings.controls, **({"courant": settings.courant} if settings.courant else {})},
                        source=dict(scene_file=str(path), settings=overrides))
    finally:
        for writer in writers:
            writer.close()
