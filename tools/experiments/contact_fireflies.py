"""RIS on the tuning neon before and after the fix of the contact fireflies (docs/measurements/error-vs-time.md,
"Contact fireflies"): per seed, the relMSE at 64, 256 and 1024 frames against a reference image, the largest value
one frame gave a pixel, and the CPU milliseconds per frame. Run it with PYTHONPATH at another checkout's python/ for
the before side.

    python -m tools.experiments.contact_fireflies --reference REF.npy [REF2.npy ...] --seeds 0,1,2,3
    python -m tools.experiments.contact_fireflies --make-reference REF.npy --frames 8192 --seed 98

The reference is F12's estimator (RIS with BSDF candidates, whose weights the BSDF bounds) over --frames frames;
given several, their mean.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import held_out
from restircl.render.frame import read_image

COUNTS = (64, 256, 1024)


def make_reference(path: str, frames: int, seed: int) -> None:
    r = Renderer(held_out("neon"), Settings(method="ris", bsdf_sampling="on", seed=seed))
    t0 = time.perf_counter()
    img = r.render_still(0, frames).color[..., :3]
    np.save(path, img)
    print(f"reference {path}: {frames} frames, seed {seed}, {time.perf_counter() - t0:.0f} s", flush=True)


def measure(ref: np.ndarray, seed: int) -> None:
    r = Renderer(held_out("neon"), Settings(method="ris", seed=seed))
    r.render_still(0, 2)  # warm-up: program build, upload
    errors: dict[int, float] = {}
    largest = [0.0]

    def at(done: int, _seconds: float) -> None:
        largest[0] = max(largest[0], float(read_image(r.device.queue, r.sample_buf, r.still.shape)[..., :3].max()))
        if done in COUNTS:
            errors[done] = rel_mse(r.still.mean_image(), ref)

    c0 = time.process_time()
    r.render_still(0, COUNTS[-1], checkpoint=at)
    cpu = time.process_time() - c0
    rel = " ".join(f"{errors[n]:.3e}" for n in COUNTS)
    print(f"seed {seed}: relMSE at {'/'.join(map(str, COUNTS))} frames {rel}; largest sample {largest[0]:.4g}; "
          f"{cpu * 1e3 / COUNTS[-1]:.1f} CPU ms per frame (with the read-backs)", flush=True)


def frame_cost(frames: int, seed: int) -> None:
    """CPU ms per frame of a still render without read-backs."""
    r = Renderer(held_out("neon"), Settings(method="ris", seed=seed))
    r.render_still(0, 2)
    c0 = time.process_time()
    r.render_still(0, frames)
    print(f"frame cost: {(time.process_time() - c0) * 1e3 / frames:.2f} CPU ms per frame ({frames} frames)",
          flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reference", nargs="*", default=[])
    ap.add_argument("--make-reference", default=None)
    ap.add_argument("--frames", type=int, default=8192)
    ap.add_argument("--seed", type=int, default=98)
    ap.add_argument("--seeds", default="0,1,2,3")
    ap.add_argument("--cost-frames", type=int, default=0, help="also time this many frames without read-backs")
    a = ap.parse_args()
    if a.make_reference:
        make_reference(a.make_reference, a.frames, a.seed)
        return
    ref = np.mean([np.load(p) for p in a.reference], axis=0)
    for s in a.seeds.split(","):
        measure(ref, int(s))
    if a.cost_frames:
        frame_cost(a.cost_frames, 0)


if __name__ == "__main__":
    main()
