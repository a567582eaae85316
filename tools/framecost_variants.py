"""Issue 23, the cost of the default ReSTIR + TAA frame: which reuse settings pay, measured side by side in one run.

    python tools/framecost_variants.py timing [--width 640 --height 360 --rounds 2]
    python tools/framecost_variants.py error [--scene many_lights|garden] [--width 192 --height 108]

`timing`: the median wall ms and CPU ms (all threads) per frame of each variant on many_lights, the variants
interleaved round by round so that a change of the shared machine's load hits them all.

`error`: equal-cost error on a moving camera. Each variant renders the animation in order with s = 1, 2, 3
samples per frame (the extra samples of a frame reuse its history and go into TAA, as in `restircl report
--moving`); the error of frames 5, 10 and 15 is taken against a converged reference of that frame.
The cost of a sample is the variant's CPU ms per sample measured in the same run (steadier than wall time on a
loaded machine). Each variant's relMSE is interpolated (log-log in cost between its sample counts) at the cost of
one and of two samples of the default, and printed beside the default's own.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np
import pyopencl as cl
from restircl.eval.bench import time_frames
from restircl.eval.held_out import held_out
from restircl.eval.metrics import rel_mse
from restircl.eval.report_reference import get_reference
from restircl.pipeline import Renderer, Settings
from restircl.scene import Scene, look_at
from restircl.scenes import many_lights

VARIANTS: dict[str, dict] = {
    "default": {},  # 8 candidates, visibility reuse, 3 spatial neighbours, pairwise MIS
    "novis": dict(visibility_reuse=False),
    "c4_novis": dict(candidates=4, visibility_reuse=False),
    "c4": dict(candidates=4),
    "n2": dict(spatial_neighbours=2),
    "novis_n2": dict(visibility_reuse=False, spatial_neighbours=2),
    "c4_novis_n2": dict(candidates=4, visibility_reuse=False, spatial_neighbours=2),
}


def load() -> str:
    return os.getloadavg().__repr__()


def timing(width: int, height: int, rounds: int, variants: dict[str, dict]) -> None:
    scene = many_lights(width=width, height=height, frames=16)
    rows: dict[str, list[tuple[float, float, dict]]] = {k: [] for k in variants}
    print(f"many_lights {width}x{height}, load {load()}")
    for _ in range(rounds):
        for name, kw in variants.items():
            ms, st = time_frames(scene, Settings(**kw), frames=6)
            rows[name].append((ms, st["cpu"], st))
    print(f"load {load()}")
    base = statistics.median(c for _, c, _ in rows["default"])
    for name, r in rows.items():
        cpu = statistics.median(c for _, c, _ in r)
        wall = statistics.median(m for m, _, _ in r)
        st = r[-1][2]
        stages = ", ".join(f"{k} {v:.1f}" for k, v in st.items() if k not in ("upload", "cpu"))
        print(f"  {name:<30} wall {wall:7.1f} ms  CPU {cpu:7.1f} ms  CPU/default {cpu / base:5.2f}   [{stages}]")


def moving_garden(width: int, height: int, frames: int = 16) -> Scene:
    """The held-out garden with its camera dollying sideways and in (about 0.35 m a frame)."""
    scene = held_out("garden", width, height)
    cams = [look_at((-3.0 + 0.4 * f, -17.0 + 0.2 * f, 7.5 - 0.1 * f), (0.4 * f - 3.0, 0.0, 0.0))
            for f in range(frames)]
    scene.camera.transforms = np.stack(cams).astype(np.float32)
    return scene.validate()


def run_variant(scene: Scene, kw: dict, samples: int, evaluated: list[int], refs: dict[int, np.ndarray],
                seed: int) -> tuple[float, float]:
    """Mean relMSE over the evaluated frames and CPU ms per sample, `samples` samples per frame."""
    r = Renderer(scene, Settings(**kw, seed=seed))
    for _ in range(2):  # kernels compile at their first launch
        r._render(0, still=False)
    r.reset()
    errs = []
    cpu = 0.0
    img = np.empty((r.height, r.width, 4), np.float32)
    for f in range(scene.frames):
        c0 = time.process_time()
        for _ in range(samples):
            _, color_buf, _ = r._render(f, still=False)
        r.device.queue.finish()
        cpu += time.process_time() - c0
        if f in refs:
            cl.enqueue_copy(r.device.queue, img, color_buf)
            errs.append(rel_mse(img[..., :3], refs[f]))
    return float(np.mean(errs)), cpu * 1e3 / (scene.frames * samples)


def at_cost(points: list[tuple[float, float]], cost: float) -> float:
    """relMSE at `cost`, log-log interpolated (or extrapolated from the two nearest) between (cost, relMSE)."""
    pts = sorted(points)
    xs = [math.log(c) for c, _ in pts]
    ys = [math.log(e) for _, e in pts]
    x = math.log(cost)
    k = 0
    while k < len(xs) - 2 and x > xs[k + 1]:
        k += 1
    t = (x - xs[k]) / (xs[k + 1] - xs[k])
    return math.exp(ys[k] + t * (ys[k + 1] - ys[k]))


def error(scene_name: str, width: int, height: int, variants: dict[str, dict], seeds: list[int],
          ref_frames: int, cache: str) -> None:
    scene = many_lights(width=width, height=height, frames=16) if scene_name == "many_lights" \
        else moving_garden(width, height)
    evaluated = list(range(5, scene.frames, 5))
    refs = {f: get_reference(scene, f, frames=ref_frames, cache_dir=cache).image for f in evaluated}
    print(f"{scene_name} {width}x{height}, moving camera, {scene.frames} frames, relMSE of frames {evaluated}; "
          f"seeds {seeds}; load {load()}")
    table: dict[str, list[tuple[float, float]]] = {}
    for name, kw in variants.items():
        pts = []
        for s in (1, 2, 3):
            e = [run_variant(scene, kw, s, evaluated, refs, seed) for seed in seeds]
            pts.append((float(np.mean([c for _, c in e])) * s, float(np.mean([x for x, _ in e]))))
        table[name] = pts
        print(f"  {name:<30} " + "  ".join(f"s={s}: {c:6.1f} CPU ms, relMSE {x:.3e}" for s, (c, x) in
                                          zip((1, 2, 3), pts, strict=True)), flush=True)
    print(f"load {load()}")
    c1 = table["default"][0][0]
    print("  equal CPU cost: relMSE at the cost of 1 and 2 default samples per frame (ratio to the default's)")
    for name, pts in table.items():
        e1, e2 = at_cost(pts, c1), at_cost(pts, 2 * c1)
        d1, d2 = at_cost(table["default"], c1), at_cost(table["default"], 2 * c1)
        print(f"  {name:<30} {e1:.3e} ({e1 / d1:4.2f})   {e2:.3e} ({e2 / d2:4.2f})")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=("timing", "error"))
    ap.add_argument("--scene", default="many_lights", choices=("many_lights", "garden"))
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--seeds", default="1,2")
    ap.add_argument("--variants", default=",".join(VARIANTS), help="comma-separated names of VARIANTS")
    ap.add_argument("--reference-frames", type=int, default=1024)
    ap.add_argument("--cache", default="out/framecost_refs")
    a = ap.parse_args()
    variants = {k: VARIANTS[k] for k in ["default", *[v for v in a.variants.split(",") if v != "default"]]}
    if a.what == "timing":
        timing(a.width or 640, a.height or 360, a.rounds, variants)
    else:
        error(a.scene, a.width or 192, a.height or 108, variants, [int(s) for s in a.seeds.split(",")],
              a.reference_frames, a.cache)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
