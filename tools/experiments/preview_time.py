"""Milliseconds per material preview icon (128x128, Blender's preview job in background bpy), restircl at
--samples preview samples and Cycles (its preview scene's own samples), interleaved, with the load:
docs/blender.md ("Material previews").

    python -m tools.experiments.preview_time [--runs 3] [--samples 16]

The first restircl icon of a process builds the kernels (PoCL's cache makes later processes quicker); the figure
is the median of the runs after it.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=3, help="icons timed per engine (%(default)s)")
    ap.add_argument("--samples", type=int, default=16, help="restircl's preview_samples (%(default)s)")
    args = ap.parse_args(argv)
    import bpy
    from restircl.eval import blender_scenes as scenes
    from restircl.io.blend import addon_module

    if not hasattr(bpy.types.Scene, "restircl"):
        addon_module().register()
    scenes.new_scene(32, 32, engine="RESTIRCL")
    bpy.context.scene.restircl.preview_samples = args.samples
    mat = scenes.diffuse_material("PreviewOrange", (0.8, 0.3, 0.1))
    t0 = time.perf_counter()
    scenes.preview_icon(mat, "RESTIRCL")
    print(f"first restircl icon (kernels built): {(time.perf_counter() - t0) * 1e3:.0f} ms")
    times: dict[str, list[float]] = {"RESTIRCL": [], "CYCLES": []}
    for _ in range(args.runs):
        for engine, ms in times.items():
            t0 = time.perf_counter()
            scenes.preview_icon(mat, engine)
            ms.append((time.perf_counter() - t0) * 1e3)
    for engine, ms in times.items():
        print(f"{engine}: median {statistics.median(ms):.0f} ms per icon ({', '.join(f'{m:.0f}' for m in ms)})")
    print(f"load (1, 5, 15 min): {', '.join(f'{x:.1f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
