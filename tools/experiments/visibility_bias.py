"""Issue 23: the bias of the visibility shortcut (Settings.visibility_max_age) on a still, converging camera.

    python -m tools.experiments.visibility_bias [--scene many_lights|garden] [--frames 256] [--runs 4] \
        [--width 192 --height 108]

Each variant renders `runs` independent runs (own seeds) of `frames` frames of a still camera (jitter on, as the
viewport), and the mean of each run's noisy frames is its image. Against the unshortcut default ("off", unbiased)
the squared bias is estimated without the noise of either side: mean over pixels of (d^2 - se_d^2) / (ref^2 +
0.01), d the difference of the two variants' run means and se_d its standard error from the runs' spread (the
relMSE normalisation of restircl.eval.metrics). Beside it: the image mean's relative difference (+- its standard
error), and the relMSE of one run's first 16 and all `frames` frames against the mean of the off runs (the noise at
practical frame counts; it includes that mean's own noise, 1/runs of it).
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from restircl import Renderer, Scene, Settings
from restircl.eval.scenes.held_out import held_out
from restircl.scenes.builtin import many_lights

VARIANTS: dict[str, dict] = {
    "off": {},
    "vis4": dict(visibility_max_age=4, visibility_max_distance=1.0),
    "vis4_d2": dict(visibility_max_age=4, visibility_max_distance=2.0),
}


def still_scene(name: str, width: int, height: int) -> Scene:
    return many_lights(width=width, height=height, frames=1) if name == "many_lights" else held_out(name, width,
                                                                                                     height)


def runs_of(scene: Scene, kw: dict, runs: int, frames: int) -> tuple[np.ndarray, np.ndarray]:
    """(runs, H, W, 3) means of all frames and of the first 16 frames of each run."""
    full, early = [], []
    for k in range(runs):
        r = Renderer(scene, Settings(**kw, seed=100 + k))
        acc = np.zeros((r.height, r.width, 3))
        for f in range(frames):
            acc += r.render_frame(0, still=True, aovs=False).noisy[..., :3]
            if f == 15:
                early.append(acc / 16)
        full.append(acc / frames)
    return np.stack(full), np.stack(early)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="many_lights", choices=("many_lights", "garden"))
    ap.add_argument("--width", type=int, default=192)
    ap.add_argument("--height", type=int, default=108)
    ap.add_argument("--frames", type=int, default=256)
    ap.add_argument("--runs", type=int, default=4)
    a = ap.parse_args()
    scene = still_scene(a.scene, a.width, a.height)
    print(f"{a.scene} {a.width}x{a.height}, still camera, {a.runs} runs x {a.frames} frames; load {os.getloadavg()}")
    res = {name: runs_of(scene, kw, a.runs, a.frames) for name, kw in VARIANTS.items()}
    off = res["off"][0]
    ref = off.mean(axis=0)
    norm = ref * ref + 0.01
    for name, (full, early) in res.items():
        d = full.mean(axis=0) - ref
        se2 = full.var(axis=0, ddof=1) / a.runs + off.var(axis=0, ddof=1) / a.runs
        bias2 = float(np.mean((d * d - se2) / norm)) if name != "off" else 0.0
        m, m0 = full.mean(axis=(1, 2, 3)), off.mean(axis=(1, 2, 3))
        rel = (m.mean() - m0.mean()) / m0.mean()
        se_rel = np.hypot(m.std(ddof=1), m0.std(ddof=1)) / np.sqrt(a.runs) / m0.mean()
        noise16 = float(np.mean([np.mean((e - ref) ** 2 / norm) for e in early]))
        noise = float(np.mean([np.mean((f - ref) ** 2 / norm) for f in full]))
        print(f"  {name:<8} squared bias (relMSE) {bias2:+.2e}   image mean {rel * 100:+.2f} % +- {se_rel * 100:.2f}"
              f"   relMSE of one run: 16 frames {noise16:.2e}, {a.frames} frames {noise:.2e}", flush=True)
    print(f"load {os.getloadavg()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
