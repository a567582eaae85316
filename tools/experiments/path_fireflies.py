"""Where the path pass's variance sits on a kind with bounces (docs/measurements/error-vs-time.md, "Garden with
bounces: the light tree beside a lamp"): F12's still settings with Max Bounces 4, N frames of one seed, the
per-pixel variance per sample of the path pass's own light (the `indirect` buffer, path/path.cl) relative to the
Cycles reference's square + 0.01 (as rel_mse), its sum over the image, the worst pixels' share and the largest
single sample; then the relMSE of the whole image at N frames and the CPU milliseconds per frame. Run it with
PYTHONPATH at another checkout's python/ for the before side.

    python -m tools.experiments.path_fireflies --kind garden --reference REF.npy --frames 256 --seed 5 \\
        --pixels 95,100 40,69
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render.frame import read_image
from restircl.render.still_method import still_settings


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", default="garden")
    ap.add_argument("--reference", required=True, help="the Cycles reference (.npy) of the kind at 192x108")
    ap.add_argument("--frames", type=int, default=256)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--pixels", nargs="*", default=[], help="x,y pixels to report besides the worst three")
    a = ap.parse_args()
    ref = np.load(a.reference)[..., :3]
    h, w = ref.shape[:2]
    scene = scene_of_kind(a.kind, w, h)
    r = Renderer(scene, replace(still_settings(Settings(max_bounces=4).validate(), scene), seed=a.seed))
    acc, acc2, top = np.zeros((h, w)), np.zeros((h, w)), np.zeros((h, w))

    def at(_done: int, _seconds: float) -> None:
        assert r.paths.indirect is not None
        light = read_image(r.device.queue, r.paths.indirect, r.still.shape)[..., :3].mean(-1)
        acc[:] += light
        acc2[:] += light**2
        np.maximum(top, light, out=top)

    img = r.render_still(0, a.frames, checkpoint=at).color[..., :3]
    mean = acc / a.frames
    var = acc2 / a.frames - mean**2
    rel = var / (ref.mean(-1) ** 2 + 0.01)
    order = np.argsort(rel.ravel())[::-1]
    print(f"{a.kind} seed {a.seed}, {a.frames} frames: path light's relative variance per sample, summed "
          f"{rel.sum():.4g}; worst 5 pixels' share {rel.ravel()[order[:5]].sum() / rel.sum():.3f}; largest sample "
          f"{top.max():.4g}; relMSE of the image {rel_mse(img, ref):.4g}")
    worst = [(int(k % w), int(k // w)) for k in order[:3]]
    for x, y in [tuple(int(v) for v in p.split(",")) for p in a.pixels] + worst:
        print(f"  pixel ({x}, {y}): path light mean {mean[y, x]:.4g}, variance per sample {var[y, x]:.4g}, largest "
              f"sample {top[y, x]:.4g}; Cycles' pixel {ref[y, x].mean():.4g}")
    r2 = Renderer(scene, replace(r.settings, seed=a.seed + 1))
    r2.render_still(0, 2)
    c0 = time.process_time()
    r2.render_still(0, a.frames // 4)
    print(f"  {(time.process_time() - c0) * 4e3 / a.frames:.1f} CPU ms per frame ({a.frames // 4} frames, "
          f"load {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
