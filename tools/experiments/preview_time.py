"""Milliseconds per material preview icon (128x128, Blender's preview job in background bpy), restircl at
--samples preview samples and Cycles (its preview scene's own samples), interleaved, with the load:
docs/blender.md ("Material previews").

    python tools/experiments/preview_time.py [--runs 3] [--samples 16]

The first restircl icon of a process builds the kernels (PoCL's cache makes later processes quicker); the figure
is the median of the runs after it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "python"), str(ROOT / "addon")]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3, help="icons timed per engine (%(default)s)")
    ap.add_argument("--samples", type=int, default=16, help="restircl's preview_samples (%(default)s)")
    args = ap.parse_args(argv)
    import bpy
    from tests.test_blender_preview import icon
    from tests.test_blender_support import ensure_registered, scenes

    ensure_registered()
    scenes.new_scene(32, 32, engine="RESTIRCL")
    bpy.context.scene.restircl.preview_samples = args.samples
    mat = scenes.diffuse_material("PreviewOrange", (0.8, 0.3, 0.1))
    t0 = time.perf_counter()
    icon(mat, "RESTIRCL")
    print(f"first restircl icon (kernels built): {(time.perf_counter() - t0) * 1e3:.0f} ms")
    times: dict[str, list[float]] = {"RESTIRCL": [], "CYCLES": []}
    for _ in range(args.runs):
        for engine, ms in times.items():
            t0 = time.perf_counter()
            icon(mat, engine)
            ms.append((time.perf_counter() - t0) * 1e3)
    for engine, ms in times.items():
        print(f"{engine}: median {statistics.median(ms):.0f} ms per icon ({', '.join(f'{m:.0f}' for m in ms)})")
    print(f"load (1, 5, 15 min): {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
