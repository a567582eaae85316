"""Issue 23, the cost of the default ReSTIR + TAA frame: which reuse settings pay, measured side by side in one run.

    python -m tools.experiments.framecost_variants timing [--width 640 --height 360 --rounds 2]
    python -m tools.experiments.framecost_variants error [--scene many_lights|garden] [--width 192 --height 108]

`timing`: the median wall ms and CPU ms (all threads) per frame of each variant on many_lights, the variants
interleaved round by round so that a change of the shared machine's load hits them all.

`error`: equal-time error on a moving camera, as in a viewport: a faster frame means more frames along the same
camera path in the same time. Each variant renders the path in 16, 31 and 46 frames (its points 1/3, 2/3 and 1 are
frames 5, 10, 15 of the 16), and its relMSE there is taken against converged references of those points. (Extra
samples of one frame, as `restircl report --moving` renders them, are blended by TAA as a still camera's, with
n growing from frame to frame: the image lags behind the camera, 10x the error at 2 samples per frame.) The time
of a path is the variant's CPU ms per frame measured in the same run (steadier than wall time on a loaded machine)
times its frames. The mean and the median relMSE over the points and seeds (the mean is dominated by the rare
firefly that TAA carries along) are interpolated, log-log in time between the frame counts, at the time of the
default's 16 and 31 frames, and printed beside the default's own.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np
import pyopencl as cl
from restircl import Renderer, Scene, Settings, look_at
from restircl.eval.bench.timing import time_frames
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.held_out import held_out
from restircl.scenes.builtin import many_lights

VARIANTS: dict[str, dict] = {
    "default": {},  # Settings(): 8 candidates, visibility reuse, 2 spatial neighbours, pairwise MIS
    "novis": dict(visibility_reuse=False),
    "c4_novis": dict(candidates=4, visibility_reuse=False),
    "c4": dict(candidates=4),
    "n2": dict(spatial_neighbours=2),
    "n1": dict(spatial_neighbours=1),
    "n3": dict(spatial_neighbours=3),
    "novis_n2": dict(visibility_reuse=False, spatial_neighbours=2),
    "c4_novis_n2": dict(candidates=4, visibility_reuse=False, spatial_neighbours=2),
    # the visibility shortcut (restir/temporal.cl): stored shadow tests within 1 or 2 pixel footprints, 4 frames
    "vis4": dict(visibility_max_age=4, visibility_max_distance=1.0),
    "vis4_d2": dict(visibility_max_age=4, visibility_max_distance=2.0),  # visibility_max_distance's default
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
    """The tuning garden with its camera dollying sideways and in along one path (6 m), in `frames` frames."""
    scene = held_out("garden", width, height)
    cams = []
    for f in range(frames):
        t = f / (frames - 1)
        cams.append(look_at((-3.0 + 6.0 * t, -17.0 + 3.0 * t, 7.5 - 1.5 * t), (6.0 * t - 3.0, 0.0, 0.0)))
    scene.camera.transforms = np.stack(cams).astype(np.float32)
    return scene.validate()


def path_scene(name: str, width: int, height: int, frames: int) -> Scene:
    """The moving-camera scene with its camera path cut into `frames` frames."""
    if name == "many_lights":
        return many_lights(width=width, height=height, frames=frames)
    return moving_garden(width, height, frames)


def run_variant(scene: Scene, kw: dict, evaluated: list[int], refs: list[np.ndarray],
                seed: int) -> tuple[list[float], float]:
    """relMSE of the evaluated frames (against refs, in order) and CPU ms per frame, every frame in order."""
    r = Renderer(scene, Settings(**kw, seed=seed))
    for _ in range(2):  # kernels compile at their first launch
        r.run_frame(0, still=False)
    r.reset()
    errs = []
    cpu = 0.0
    img = np.empty((r.height, r.width, 4), np.float32)
    for f in range(scene.frames):
        c0 = time.process_time()
        _, color_buf, _ = r.run_frame(f, still=False)
        r.device.queue.finish()
        cpu += time.process_time() - c0
        if f in evaluated:
            cl.enqueue_copy(r.device.queue, img, color_buf)
            errs.append(rel_mse(img[..., :3], refs[evaluated.index(f)]))
    return errs, cpu * 1e3 / scene.frames


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
    base = path_scene(scene_name, width, height, 16)
    evaluated = [5, 10, 15]
    refs = [get_reference(base, f, frames=ref_frames, cache_dir=cache).image for f in evaluated]
    print(f"{scene_name} {width}x{height}, moving camera: one path in 16, 31 and 46 frames (speed 1, 1/2, 1/3), "
          f"relMSE at its points 1/3, 2/3 and 1; seeds {seeds}; load {load()}")
    # per variant and statistic (mean, median over the evaluated points and seeds): (CPU ms for the path, relMSE)
    table: dict[str, dict[str, list[tuple[float, float]]]] = {}
    for name, kw in variants.items():
        pts: dict[str, list[tuple[float, float]]] = {"mean": [], "median": []}
        for k in (1, 2, 3):
            scene = path_scene(scene_name, width, height, 15 * k + 1)
            runs = [run_variant(scene, kw, [k * f for f in evaluated], refs, seed) for seed in seeds]
            cost = float(np.mean([c for _, c in runs])) * scene.frames
            errs = [e for run, _ in runs for e in run]
            pts["mean"].append((cost, float(np.mean(errs))))
            pts["median"].append((cost, float(np.median(errs))))
        table[name] = pts
        print(f"  {name:<14} " + "  ".join(f"{15 * k + 1} frames: {c / (15 * k + 1):5.1f} CPU ms/frame, relMSE mean "
                                          f"{x:.3e} median {m:.3e}"
                                          for k, (c, x), (_, m) in zip((1, 2, 3), pts["mean"], pts["median"],
                                                                       strict=True)), flush=True)
    print(f"load {load()}")
    c1 = table["default"]["mean"][0][0]
    print("  equal CPU time for the path: relMSE (mean, median) at the time of the default's 16 and 31 frames "
          "(interpolated), and its ratio to the default's")
    for name, pts in table.items():
        cells = []
        for budget in (c1, table["default"]["mean"][1][0]):
            for stat in ("mean", "median"):
                e, d = at_cost(pts[stat], budget), at_cost(table["default"][stat], budget)
                cells.append(f"{stat} {e:.3e} ({e / d:4.2f})")
        print(f"  {name:<14} 16: {cells[0]}, {cells[1]}   31: {cells[2]}, {cells[3]}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=("timing", "error"))
    ap.add_argument("--scene", default="many_lights", choices=("many_lights", "garden"))
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--seeds", default="1,2,3,4")
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
