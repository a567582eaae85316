"""Our still's variance between seeds at the silhouettes against a black world, without a reference: per sample
count N, the variance of 4 seeds' renders (absolute, the colours' mean), times N (constant: the Monte Carlo rate 1/N;
falling: faster), on the silhouette pixels and on the whole image. For comparing variants of the pixel jitter, each
with PYTHONPATH at its own tree (edge_convergence.py measures the alpha scene against Cycles).

    EDGE_MASK=mask.npy PYTHONPATH=python python tools/experiments/edge_variance.py [cornell|alpha [seeds [mode]]]

mode (for splitting the variance into its parts): `nojitter` (no pixel jitter: the shading's variance alone),
`random` (the random sampler instead of Sobol, the same candidates), `random-nojitter`, `emissive` (the alpha scene's
floor lit by its own emission only, which no light sample changes: the pixel jitter's coverage estimate alone).

The silhouette pixels: those whose centre sees a surface next to one whose centre sees the world (a render without
jitter); picked on the first run and written to EDGE_MASK, read by later runs, so every variant is measured on the
same pixels.
"""

from __future__ import annotations

import dataclasses
import os
import sys
import time

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.scenes.alpha_cards import alpha_cards
from restircl.scenes.builtin import cornell_box

COUNTS = (64, 256, 1024)


def silhouette(scene) -> np.ndarray:
    img = Renderer(scene, still_settings(Settings(jitter=False), scene)).render_still(0, samples=4).color[..., :3]
    hit = img.max(axis=-1) > 0.0
    near_miss = np.zeros_like(hit)
    for axis in (0, 1):
        for step in (1, -1):
            near_miss |= ~np.roll(hit, step, axis=axis)
    near_miss[0, :] = near_miss[-1, :] = near_miss[:, 0] = near_miss[:, -1] = False  # roll wraps around
    return hit & near_miss


def settings(scene, seed: int, mode: str) -> Settings:
    s = still_settings(Settings(seed=seed), scene)
    if "random" in mode:
        s = dataclasses.replace(s, sampler="random")
    return dataclasses.replace(s, jitter=False) if "nojitter" in mode else s


def main() -> None:
    name = sys.argv[1] if len(sys.argv) > 1 else "cornell"
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    mode = sys.argv[3] if len(sys.argv) > 3 else "default"
    scene = cornell_box(64, 64) if name == "cornell" else alpha_cards(96, 72)
    if mode == "emissive":
        floor = scene.materials[0]
        floor.albedo, floor.emission, floor.emission_strength = (0.0, 0.0, 0.0), (1.0, 1.0, 1.0), 1.0
    t0 = time.process_time()
    mask_path = os.environ.get("EDGE_MASK", f"/tmp/edge_silhouette_{name}.npy")
    if not os.path.exists(mask_path):
        np.save(mask_path, silhouette(scene))
    edge = np.load(mask_path)
    imgs = {n: np.stack([Renderer(scene, settings(scene, s, mode)).render_still(0, samples=n).color[..., :3]
                         for s in range(1, seeds + 1)]) for n in COUNTS}
    print(f"{name} {mode}, {edge.sum()} silhouette pixels, seeds 1-{seeds}, load {os.getloadavg()[0]:.1f}")
    for n in COUNTS:
        v = imgs[n].var(axis=0, ddof=1).mean(axis=-1)
        print(f"N={n:5d}: variance x N silhouette {n * v[edge].mean():.3f}, whole {n * v.mean():.4f}; "
              f"variance silhouette {v[edge].mean():.2e}, whole {v.mean():.2e}", flush=True)
    print(f"CPU {time.process_time() - t0:.0f} s, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
