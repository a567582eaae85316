"""Where the motion-blurred animation's error lies: the add-on's animation frames (ReSTIR DI + TAA) rendered with a
shutter of --shutter frames and sharp, each against the same converged motion-blurred reference of its frame
(eval/report/reference.py, cached as tools/experiments/motion_blur_animation.py caches it), over several seeds.
Per run it prints the mean relMSE of the evaluated frames, the same with each frame's 5 worst pixels left out (a
lamp hit by one frame's sample under a reset history is one pixel whose error can outweigh the rest of the image),
the share of the error in each frame's 20 worst pixels, and the light of the lamps' pixels (reference above 2)
against the reference's: docs/design.md, "Depth of field and motion blur in motion".

    python -m tools.experiments.motion_blur_animation_errors --scene many_lights --seeds 0 1 2 3
    python -m tools.experiments.motion_blur_animation_errors --scene moving_box --seeds 0 1
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import numpy as np
from restircl.eval.metrics import rel_mse_map
from restircl.eval.report.reference import get_reference
from restircl.render.pipeline import Renderer
from restircl.scene.scene import Scene
from restircl.scenes.builtin import many_lights, moving_box
from restircl.settings.table import Settings

FRAMES = 24
EVALUATED = (5, 11, 17, 23)
TRIM = 5  # worst pixels left out per frame
LAMP = 2.0  # a reference pixel above this (mean of RGB) is a lamp's


def figures(images: dict[int, np.ndarray], refs: dict[int, np.ndarray]) -> dict:
    full, trimmed, top, lamps = [], [], [], []
    for k in EVALUATED:
        e = np.sort(rel_mse_map(images[k], refs[k]).ravel())[::-1]
        full.append(e.mean())
        trimmed.append(e[TRIM:].sum() / e.size)
        top.append(e[:20].sum() / max(e.sum(), 1e-30))
        r, x = refs[k][..., :3].mean(-1), images[k][..., :3].mean(-1)
        lamp = r > LAMP
        lamps.append(float(x[lamp].sum() / r[lamp].sum()) if lamp.any() else float("nan"))
    return {"rel_mse": float(np.mean(full)), "trimmed": float(np.mean(trimmed)),
            "top20_share": [round(float(t), 3) for t in top], "lamp_light": [round(v, 3) for v in lamps]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=("moving_box", "many_lights"), default="many_lights")
    ap.add_argument("--seeds", type=int, nargs="+", default=[0])
    ap.add_argument("--speed", type=float, default=0.2)
    ap.add_argument("--shutter", type=float, default=1.0)
    ap.add_argument("--ref-seconds", type=float, default=20.0)
    a = ap.parse_args()

    def make(blurred: bool) -> Scene:
        sc = many_lights(96, 54, frames=FRAMES) if a.scene == "many_lights" else moving_box(
            96, 54, frames=FRAMES, speed=a.speed)
        assert sc.camera is not None
        if blurred:
            sc.camera.shutter = (-0.5 * a.shutter, 0.5 * a.shutter)
        return sc

    cache = Path(tempfile.gettempdir()) / "restircl_motion_blur_refs"
    refs = {k: get_reference(make(True), k, a.ref_seconds, cache_dir=cache).image[..., :3] for k in EVALUATED}
    for seed in a.seeds:
        row: dict = {"scene": a.scene, "seed": seed, "load": os.getloadavg()[0]}
        for name, blurred in (("blurred", True), ("sharp", False)):
            r = Renderer(make(blurred), Settings(seed=seed))
            images = {}
            for k in range(FRAMES):
                out = r.render_frame(k)
                if k in EVALUATED:
                    images[k] = out.color[..., :3].copy()
            row[name] = figures(images, refs)
        print(json.dumps(row))


if __name__ == "__main__":
    main()
