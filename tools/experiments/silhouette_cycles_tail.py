"""Cycles' estimate of a few pixels at the gold sphere's rim on the `user` kind (issue 37), seed by seed: many
independent Cycles renders of a small border region around them (the rest of the frame is not rendered), so the
spread of one pixel's estimate across seeds shows whether its mean is carried by rare large samples (a heavy tail
that two halves of a reference need not show). docs/measurements/error-vs-time.md, "user: the metals' silhouettes".

    nice python -m tools.experiments.silhouette_cycles_tail --seeds 16 --spp 256
"""

from __future__ import annotations

import argparse

import numpy as np
from restircl.eval.cycles import bridge
from restircl.eval.cycles.compare import scene_pair

BORDER = (46, 48, 58, 62)  # x0, y0, x1, y1 of the 192 x 108 frame, rows from the top
PIXELS = ((54, 51), (55, 51), (56, 51), (57, 51))
WIDTH, HEIGHT = 192, 108


def _border(sc, box=BORDER) -> None:
    x0, y0, x1, y1 = box
    sc.render.use_border = True
    sc.render.use_crop_to_border = False
    sc.render.border_min_x, sc.render.border_max_x = x0 / WIDTH, x1 / WIDTH
    sc.render.border_min_y, sc.render.border_max_y = 1.0 - y1 / HEIGHT, 1.0 - y0 / HEIGHT


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--seeds", type=int, default=16)
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--variant", default="", choices=("", "noterm", "flat"))
    p.add_argument("--border", default=None, help="x0,y0,x1,y1 (rows from the top) instead of the gold rim's")
    p.add_argument("--pixels", default=None, help="y:x,y:x,... inside the border instead of the gold rim's")
    a = p.parse_args()
    box = tuple(int(v) for v in a.border.split(",")) if a.border else BORDER
    pixels = [tuple(int(v) for v in q.split(":")) for q in a.pixels.split(",")] if a.pixels else list(PIXELS)
    import bpy

    _, sc = scene_pair("user", WIDTH, HEIGHT)
    if a.variant == "flat":  # every mesh flat-shaded
        for ob in bpy.data.objects:
            if ob.type == "MESH":
                for f in ob.data.polygons:
                    f.use_smooth = False
    if a.variant == "noterm":
        for ob in bpy.data.objects:
            if ob.type == "MESH":
                ob.shadow_terminator_geometry_offset = 0.0
    vals = []
    for seed in range(a.seeds):
        img = bridge.render(sc, samples=a.spp, seed=1000 + seed, threads=2, adjust=lambda sc: _border(sc, box)).image
        vals.append([float(img[y, x, :3].mean()) for y, x in pixels])
        print(f"seed {seed}: " + "  ".join(f"{v:8.3f}" for v in vals[-1]), flush=True)
    v = np.array(vals)
    for k, (y, x) in enumerate(pixels):
        col = v[:, k]
        print(
            f"({y},{x}) mean {col.mean():.3f} +- {col.std(ddof=1) / np.sqrt(len(col)):.3f}  median {np.median(col):.3f}"
            f"  max {col.max():.3f}"
        )


if __name__ == "__main__":
    main()
