"""Time the add-on's per-frame host work in an animation render through bpy (issue 23, "cheaper samples"):
`render_frame` (the renderer's frame with its read-back) and `write_result` (the Frame into Blender's Render
Result), per frame, median over the frames after the first.

    python -m tools.experiments.bench_write_result [--width 192 --height 108 --frames 24] [--passes all|none]

`--passes all` turns on every pass the add-on writes (Depth, Normal, Vector, Noisy Direct, Diffuse Color), `none`
turns them off (Combined only). Needs bpy and a device (PoCL).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import bpy
import restircl
from restircl.eval import blender_scenes as scenes
from restircl.io.blend import addon_module


def build(width: int, height: int, frames: int, all_passes: bool):
    sc = scenes.comparison_scene("mixed", width, height)
    sc.render.engine = "RESTIRCL"
    sc.frame_start, sc.frame_end = 1, frames
    vl = sc.view_layers[0]
    if all_passes:
        vl.use_pass_z = vl.use_pass_normal = vl.use_pass_vector = vl.use_pass_diffuse_color = True
        vl.restircl.use_pass_noisy_direct = True
    else:
        vl.use_pass_z = vl.use_pass_normal = vl.use_pass_vector = vl.use_pass_diffuse_color = False
        vl.restircl.use_pass_noisy_direct = False
    return sc


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--height", type=int, default=108)
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--passes", choices=("all", "none"), default="all")
    a = ap.parse_args(argv)
    addon = addon_module()
    render_result = addon.render_result
    if not hasattr(bpy.types.Scene, "restircl"):
        addon.register()
    sc = build(a.width, a.height, a.frames, a.passes == "all")
    times: dict[str, list[float]] = {"render_frame": [], "write_result": []}
    original_write = render_result.write_result

    def timed_write(*args, **kwargs):
        t0 = time.perf_counter()
        original_write(*args, **kwargs)
        times["write_result"].append((time.perf_counter() - t0) * 1e3)

    render_result.write_result = timed_write
    renderer_cls = restircl.Renderer
    original_frame = renderer_cls.render_frame

    def timed_frame(self, *args, **kwargs):
        t0 = time.perf_counter()
        out = original_frame(self, *args, **kwargs)
        times["render_frame"].append((time.perf_counter() - t0) * 1e3)
        return out

    renderer_cls.render_frame = timed_frame
    with tempfile.TemporaryDirectory() as tmp:
        scenes.exr_output(sc, str(Path(tmp) / "f_"))
        t0 = time.perf_counter()
        bpy.ops.render.render(animation=True)
        wall = time.perf_counter() - t0
    render_result.write_result = original_write
    renderer_cls.render_frame = original_frame
    print(f"{a.width}x{a.height}, {a.frames} frames, passes {a.passes}: {wall / a.frames * 1e3:.1f} ms of wall time "
          "per frame (bpy.ops.render.render, EXR writes included)")
    for k, v in times.items():
        rest = v[1:] or v
        print(f"  {k}: median {statistics.median(rest):.2f} ms per frame (frames 2..{len(v)})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
