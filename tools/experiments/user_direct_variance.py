"""The variance of F12's estimator (`auto`) on `user`'s direct light, by parts: two renders at equal frames (seeds
7 and 8), one render's variance from their difference, weighed as rel_mse weighs it against the cached Cycles
reference (`restircl compare` makes it), over the image and per object (our object-index pass), and each render's
relMSE. Frames, not seconds: the figure does not move with the machine's load. Run from a tree to measure its code
(PYTHONPATH). docs/measurements/error-vs-time.md, "the Linear world sampled by its bilinear patches".

    nice python -m tools.experiments.user_direct_variance --frames 890 --cache-dir out/cache --out out/var.npz
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

import numpy as np
from restircl.eval.cycles.compare import cycles_reference, ours_settings, scene_pair
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH
from restircl.render.pipeline import Renderer

from tools.experiments.user_direct_probe import build, object_names


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--frames", type=int, default=890)
    p.add_argument("--seeds", default="7,8")
    p.add_argument("--reference-spp", type=int, default=1024)
    p.add_argument("--cache-dir", default="out/cache")
    p.add_argument("--out", default=None, help="an .npz of the renders, the reference and the object index")
    a = p.parse_args()
    scene, sc = scene_pair("user", WIDTH, HEIGHT)
    ref = cycles_reference("user", scene, sc, a.reference_spp, 2, Path(a.cache_dir), lambda *x: None).image
    scene, _ = build(WIDTH, HEIGHT, "all")  # the same scene, its objects numbered by pass index
    names = ["(none)", *object_names()]
    base = ours_settings("auto", scene)
    idx_frame = Renderer(scene, replace(base, light_passes=True)).render_still(0, 1)
    idx = np.rint(np.asarray(idx_frame.object_index, np.float64)).astype(int)
    imgs = []
    for seed in (int(s) for s in a.seeds.split(",")):
        img = Renderer(scene, replace(base, seed=seed)).render_still(0, a.frames).color[..., :3].astype(np.float64)
        imgs.append(img)
        print(f"seed {seed}: relMSE {rel_mse(img, ref):.3e}", flush=True)
    w = 1.0 / (ref.astype(np.float64) ** 2 + 0.01)
    var = np.mean((imgs[0] - imgs[1]) ** 2 / 2 * w, axis=-1)  # one render's variance, per pixel
    print(f"one render's variance (relMSE weighing) over the image {var.mean():.3e}")
    for i in np.unique(idx):
        share = var[idx == i].sum() / var.size
        name = names[i] if 0 <= i < len(names) else str(i)
        top = var[idx == i].max() / var.size
        print(f"  {name}: {np.count_nonzero(idx == i)} px, {share:.2e} of it; top pixel {top:.1e}")
    if a.out:
        np.savez_compressed(a.out, renders=np.stack(imgs), reference=ref, object_index=idx)


if __name__ == "__main__":
    main()
