"""Where the error of F12's first frames sits on a kind (docs/measurements/error-vs-time.md, "Issue 37 on every
kind, after the tree's changes"): for each seed a fresh Renderer (as `restircl compare` times one) with F12's
still settings and the Light Paths given, `frames` frames; per seed the image's relMSE against the Cycles reference
of the same Light Paths, the 5 worst pixels' share of it, the share of the error on pixels whose path-pass light
(the `indirect` buffer, path/path.cl) is above the reference's pixel, and the largest path sample; then the worst
pixels of the worst seed with their image, path light and reference values, and the CPU milliseconds per frame.

    python -m tools.experiments.first_frame_error --kind user --reference REF.npy --max-bounces 4 --frames 1 \\
        --seeds 1000-1015

--light-proposal tree: the first hit's RIS candidates from the light tree too (docs/measurements/error-vs-time.md,
"Distant lights picked at the point").
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.cycles.compare import scene_pair
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.metrics import rel_mse_map
from restircl.render.frame import read_image
from restircl.render.still_method import still_settings


def seeds_of(text: str) -> list[int]:
    """'1000-1003' or '1,5,9' -> the seeds."""
    if "-" in text:
        lo, hi = (int(v) for v in text.split("-"))
        return list(range(lo, hi + 1))
    return [int(v) for v in text.split(",")]


def error_split(img: np.ndarray, ref: np.ndarray, path: np.ndarray) -> dict:
    """relMSE of img (H, W, 3) against ref, the shares of it on its 5 and 50 worst pixels, and the share on the
    pixels whose path-pass light (path, H x W x 3) has a channel mean above the reference's, with their count."""
    err = rel_mse_map(img, ref)
    total = float(err.sum())
    worst = np.sort(err.ravel())[::-1]
    heavy = path.mean(-1) > ref.mean(-1)
    share = (lambda v: float(v) / total) if total > 0 else (lambda v: 0.0)
    return {"rel_mse": total / err.size, "worst5": share(worst[:5].sum()), "worst50": share(worst[:50].sum()),
            "path_heavy": share(err[heavy].sum()), "path_heavy_pixels": int(heavy.sum())}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", default="user")
    ap.add_argument("--reference", required=True, help="the Cycles reference (.npy) of the kind, same Light Paths")
    ap.add_argument("--max-bounces", type=int, default=4)
    ap.add_argument("--frames", type=int, default=1)
    ap.add_argument("--seeds", default="1000-1007")
    ap.add_argument("--light-proposal", default=None, help="Settings.light_proposal in place of F12's (e.g. tree)")
    a = ap.parse_args()
    ref = np.load(a.reference)[..., :3].astype(np.float64)
    h, w = ref.shape[:2]
    scene, _ = scene_pair(a.kind, w, h)
    base = still_settings(Settings(**LightPaths.of(a.max_bounces).overrides()).validate(), scene)
    if a.light_proposal:
        base.light_proposal = a.light_proposal
    Renderer(scene, base).render_still(0, 1)  # the kernels' build, outside the timed frames
    worst_seed: tuple[float, int, np.ndarray, np.ndarray] | None = None
    cpu, frames_done = 0.0, 0
    for seed in seeds_of(a.seeds):
        base.seed = seed
        r = Renderer(scene, base)
        path = np.zeros((h, w, 3))
        top = np.zeros((h, w))

        def at(_done: int, _seconds: float, r: Renderer = r, path: np.ndarray = path, top: np.ndarray = top) -> None:
            if r.paths is not None and r.paths.indirect is not None:
                light = read_image(r.device.queue, r.paths.indirect, r.still.shape)[..., :3]
                path[:] += light
                np.maximum(top, light.mean(-1), out=top)

        c0 = time.process_time()
        img = r.render_still(0, a.frames, checkpoint=at).color[..., :3].astype(np.float64)
        cpu += time.process_time() - c0
        frames_done += a.frames
        path /= a.frames
        split = error_split(img, ref, path)
        print(f"seed {seed}: relMSE {split['rel_mse']:.4g}; worst 5 pixels' share {split['worst5']:.3f}, worst 50 "
              f"{split['worst50']:.3f}; share on pixels whose path light exceeds the reference "
              f"{split['path_heavy']:.3f} ({split['path_heavy_pixels']} px); largest path sample {top.max():.4g}",
              flush=True)
        total = split["rel_mse"]
        if worst_seed is None or total > worst_seed[0]:
            worst_seed = (float(total), seed, img, path)
    assert worst_seed is not None
    _, seed, img, path = worst_seed
    err = rel_mse_map(img, ref)
    for k in np.argsort(err.ravel())[::-1][:8]:
        y, x = divmod(int(k), w)
        print(f"  seed {seed} pixel ({x}, {y}): share {err[y, x] / err.sum():.3f}, image {img[y, x].mean():.4g}, path "
              f"light {path[y, x].mean():.4g}, reference {ref[y, x].mean():.4g}")
    print(f"  {cpu * 1e3 / frames_done:.1f} CPU ms per frame in render_still (the upload before it not counted; "
          f"load {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
