"""The path pass's NEE from the light tree with and without the stratified descent of its Sobol word (issue 37):
still renders with bounces at equal frames, their relMSE against a converged image and their CPU time per frame
(docs/measurements/error-vs-time.md, "The path pass's tree descent, stratified").

The two arms are two checkouts of the code (run this file once with PYTHONPATH at each): both render the same
frames with the same seeds; only the NEE pick at path vertices differs. The reference is rendered with the random
sampler (no Sobol words anywhere, so the two checkouts render it alike) and cached under --cache-dir, so both arms
score against the very same image.

    PYTHONPATH=<checkout>/python python -m tools.experiments.path_descent --kinds gi_tuning_room,interior --tag after
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.gi_tuning import gi_tuning
from restircl.eval.scenes.validation import validation


def scene_of(kind: str, width: int, height: int):
    return gi_tuning(kind, width, height) if kind.startswith("gi_tuning") else validation(kind, width, height)


def paths(bounces: int, **kw) -> Settings:
    return Settings(method="ris", max_bounces=bounces, diffuse_bounces=bounces, glossy_bounces=bounces,
                    **kw).validate()


def reference(kind: str, scene, bounces: int, frames: int, cache_dir: Path) -> np.ndarray:
    cam = scene.camera
    path = cache_dir / f"{kind}_{cam.width}x{cam.height}_b{bounces}_random_ref{frames}.npy"
    if path.exists():
        return np.load(path)
    img = Renderer(scene, paths(bounces, sampler="random", candidates=16, seed=4242)).render_still(0, frames)
    out = img.color[..., :3].astype(np.float32)
    cache_dir.mkdir(parents=True, exist_ok=True)
    np.save(path, out)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--kinds", default="gi_tuning_room,interior")
    ap.add_argument("--width", type=int, default=96)
    ap.add_argument("--height", type=int, default=54)
    ap.add_argument("--bounces", type=int, default=4)
    ap.add_argument("--frames", default="16,64")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--ref-frames", type=int, default=2048)
    ap.add_argument("--cache-dir", default="out/path_descent")
    ap.add_argument("--tag", default="")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    load0 = os.getloadavg()[0]
    rows = []
    for kind in a.kinds.split(","):
        scene = scene_of(kind, a.width, a.height)
        ref = reference(kind, scene, a.bounces, a.ref_frames, Path(a.cache_dir))
        for frames in map(int, a.frames.split(",")):
            errs, cpu = [], []
            for seed in range(a.first_seed, a.first_seed + a.seeds):
                r = Renderer(scene, paths(a.bounces, seed=seed))
                assert r.path_light_tree, f"{kind}: the path pass does not pick from the tree"
                r.render_still(0, 1)  # uploads and kernel builds out of the timing
                t0 = time.process_time()
                img = r.render_still(0, frames).color[..., :3]
                cpu.append((time.process_time() - t0) / frames * 1e3)
                errs.append(rel_mse(img, ref))
            print(f"{a.tag} {kind} {frames} frames: relMSE {' '.join(f'{e:.4g}' for e in errs)} mean "
                  f"{np.mean(errs):.4g}, CPU ms/frame {np.median(cpu):.1f}", flush=True)
            rows.append({"kind": kind, "frames": frames, "rel_mse": errs, "cpu_ms_per_frame": cpu})
    load1 = os.getloadavg()[0]
    print(f"load {load0:.1f} -> {load1:.1f}")
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(json.dumps({"tag": a.tag, "width": a.width, "height": a.height,
                                           "bounces": a.bounces, "load": [load0, load1], "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
