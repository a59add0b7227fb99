"""Files written whole or not at all: a reader, or a run stopped meanwhile, sees the old
file or the new one, never half of either (probes.json, probes.csv on resume, run.json,
results.json, the sweep's tables)."""

from __future__ import annotations

import os
from pathlib import Path


def write_text(path, text: str) -> Path:
    """Write `text` to `path` through a temporary file beside it (flushed to disk) and a
    rename; on any failure, Ctrl-C included, the temporary file is removed."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path
