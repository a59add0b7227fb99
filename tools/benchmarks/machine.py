"""The processor a benchmark ran on, for its header line.

The VM this project is developed on has changed hardware under it from one day to the
next: on 2026-12-06 the engine's code of 2026-12-02 ran at 0.6 of the hand-fused
reference where it had run at 0.85-0.95 (docs/performance.md). A timing is read against
the processor it was taken on, so the benchmarks print it.
"""

from pathlib import Path


def cpu() -> str:
    """"model name (family F model M), L2 S per core" from /proc/cpuinfo and sysfs (Linux);
    what cannot be read is left out, and "unknown CPU" if nothing can."""
    fields = {}
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            key = key.strip()
            if key in ("model name", "cpu family", "model") and key not in fields:
                fields[key] = value.strip()
            if not line.strip() and fields:  # the first processor's block is enough
                break
    except OSError:
        pass
    text = fields.get("model name", "unknown CPU")
    if "cpu family" in fields and "model" in fields:
        text += f" (family {fields['cpu family']} model {fields['model']})"
    try:
        l2 = Path("/sys/devices/system/cpu/cpu0/cache/index2/size").read_text().strip()
        text += f", L2 {l2} per core"
    except OSError:
        pass
    return text


if __name__ == "__main__":
    print(cpu())
