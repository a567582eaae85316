"""What the error of an estimator through TAA on an orbiting camera is made of: docs/measurements/
temporal-stability.md, "TAA's floor taken apart".

Every mode renders the orbit one frame per animation frame (k = 1, as `restir_motion --equal-frames`) and takes the
relMSE of frames 4, 8, ..., 20, 23 against their converged references (eval/report/reference.py, cached), per seed:

- `taa`: the animation as rendered (the TAA output);
- `oracle_history`: the same, but before an evaluated frame's TAA the colour of its history (the last frame's TAA
  output) is replaced by the converged reference of the last frame (its history length n kept): what is left is
  the current frame's noise through one blend, and one step of reprojection and clipping;
- `converged_input`: TAA fed the converged reference of every frame in place of the frame's sample: TAA's own
  error without noise (the bilinear history's blur under motion, the clip of a box built from converged colours);
- `converged_both`: both: one step of reprojection and clipping alone, without noise;
- `single`: no TAA, the frame's own sample (its noise per frame, E1);
- `average`: no TAA, the mean of K independent samples of the same frame (K = 1, 2, 4, 8): noise that falls as 1/K.

Beside each TAA mode, the share of the error on pixels whose history was rejected this frame (n = 1: disoccluded,
or off-screen last frame) and on young histories (n <= 4), and the share of such pixels.

    python -m tools.experiments.taa_floor --scene garden_orbit --methods ris+candidates=256,restir --seeds 4
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl.eval.metrics import rel_mse_map
from restircl.eval.report.methods import method_settings
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import motion_scene
from restircl.render.frame import read_image
from restircl.render.pipeline import Renderer

from .restir_motion import orbit_arguments

TAA_MODES = ("taa", "oracle_history", "converged_input", "converged_both")
AVERAGE_KS = (1, 2, 4, 8)


def renderer(scene, method: str, seed: int) -> Renderer:
    r = Renderer(scene, method_settings(method, None, seed))
    for _ in range(2):  # warm-up (kernels compile at their first launch); then start without history
        r.run_frame(0, still=False)
    r.reset()
    return r


def _write_rgb(r: Renderer, buf: cl.Buffer, rgb: np.ndarray) -> None:
    """Replace the rgb of a float4 image buffer, keeping its w (the TAA history's length n)."""
    q = r.device.queue
    img = read_image(q, buf, (r.height, r.width))
    img[..., :3] = rgb
    cl.enqueue_copy(q, buf, np.ascontiguousarray(img))
    q.finish()


def taa_run(scene, method: str, seed: int, mode: str, refs: dict[int, np.ndarray],
            evaluated: list[int]) -> dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """{frame: (TAA output, history length n, the frame's sample)} at the evaluated frames of the orbit in `mode`
    (TAA_MODES)."""
    r = renderer(scene, method, seed)
    stage = r.taa
    plain = stage.run
    now = {"frame": 0}

    def run(state, moving):  # the TAA stage with its input or its history replaced (the mode)
        f, h = now["frame"], r.history
        if mode == "converged_input" or (mode == "converged_both" and f in evaluated):
            _write_rgb(r, r.buffers.sample, refs[f])
        if mode in ("oracle_history", "converged_both") and f in evaluated and h.valid:  # the frames read
            _write_rgb(r, h.taa[h.prev], refs[f - 1])
        return plain(state, moving)

    stage.run = run  # type: ignore[method-assign]
    out = {}
    for f in range(scene.frames):
        now["frame"] = f
        _, color, _ = r.run_frame(f, still=False)
        if f in evaluated:
            img = read_image(r.device.queue, color, (r.height, r.width))[..., :3]
            out[f] = (img, r.history_length(), read_image(r.device.queue, r.sample_buf, (r.height, r.width))[..., :3])
    return out


def sample_images(scene, method: str, seed: int, evaluated: list[int], k: int) -> dict[int, list[np.ndarray]]:
    """{frame: its first k samples} (no TAA: the frame's sample buffer, rendered k times at the frame; the jitter
    moves on every time, as along TAA's frames)."""
    r = renderer(scene, method, seed)
    out: dict[int, list[np.ndarray]] = {}
    for f in evaluated:
        out[f] = []
        for _ in range(k):
            r.run_frame(f, still=False)
            out[f].append(read_image(r.device.queue, r.sample_buf, (r.height, r.width))[..., :3].copy())
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--methods", default="ris+candidates=256")
    ap.add_argument("--modes", default=",".join(TAA_MODES), help="TAA modes, comma-separated (TAA_MODES)")
    ap.add_argument("--single", default="", help="methods whose samples are measured without TAA (single, average)")
    ap.add_argument("--average", type=int, default=8, help="K of the average mode (1 for single only)")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--ref-seconds", type=float, default=10.0)
    ap.add_argument("--cache-dir", default="out/refs")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    evaluated = sorted({*range(a.every, scene.frames, a.every), scene.frames - 1})
    modes = [m for m in a.modes.split(",") if m]
    needed = set(evaluated)
    if "oracle_history" in modes or "converged_both" in modes:
        needed |= {f - 1 for f in evaluated}
    if "converged_input" in modes:
        needed |= set(range(scene.frames))
    refs, ref_err = {}, {}
    for f in sorted(needed):
        ref = get_reference(scene, f, a.ref_seconds, cache_dir=Path(a.cache_dir), log=lambda s: None)
        refs[f], ref_err[f] = ref.image, ref.est_rel_mse
    t0, load0 = time.time(), os.getloadavg()[0]
    rows = []
    for method in [m for m in a.methods.split(",") if m]:
        for mode in modes:
            per_seed, disocc, young, disocc_px, young_px, frames, raw = [], [], [], [], [], [], []
            for seed in range(1, a.seeds + 1):
                got = taa_run(scene, method, seed, mode, refs, evaluated)
                maps = {f: rel_mse_map(img, refs[f]) for f, (img, _, _) in got.items()}
                raw.append(float(np.mean([rel_mse_map(got[f][2], refs[f]).mean() for f in evaluated])))
                frames.append([float(maps[f].mean()) for f in evaluated])
                per_seed.append(float(np.mean(frames[-1])))
                total = sum(float(m.sum()) for m in maps.values())
                disocc.append(sum(float(maps[f][got[f][1] <= 1.0].sum()) for f in evaluated) / total)
                young.append(sum(float(maps[f][got[f][1] <= 4.0].sum()) for f in evaluated) / total)
                disocc_px.append(float(np.mean([np.mean(got[f][1] <= 1.0) for f in evaluated])))
                young_px.append(float(np.mean([np.mean(got[f][1] <= 4.0) for f in evaluated])))
            row = {"method": method, "mode": mode, "rel_mse_per_seed": per_seed, "mean": float(np.mean(per_seed)),
                   "median": float(np.median(per_seed)), "per_frame": np.mean(frames, axis=0).tolist(),
                   "share_n1": float(np.mean(disocc)), "share_n4": float(np.mean(young)),
                   "pixels_n1": float(np.mean(disocc_px)), "pixels_n4": float(np.mean(young_px)),
                   "sample_rel_mse_per_seed": raw, "sample_mean": float(np.mean(raw))}
            rows.append(row)
            print(f"{method:<28} {mode:<16} mean {row['mean']:.4f} median {row['median']:.4f}  per seed "
                  f"{' '.join(f'{e:.4f}' for e in per_seed)}  error on n=1 {row['share_n1']:.1%} "
                  f"({row['pixels_n1']:.1%} of pixels), n<=4 {row['share_n4']:.1%} ({row['pixels_n4']:.1%}); "
                  f"its samples without TAA {row['sample_mean']:.4f}",
                  flush=True)
    for method in [m for m in a.single.split(",") if m]:
        by_k: dict[int, list[float]] = {k: [] for k in AVERAGE_KS if k <= a.average}
        for seed in range(1, a.seeds + 1):
            got = sample_images(scene, method, seed, evaluated, a.average)
            for k in by_k:
                by_k[k].append(float(np.mean([rel_mse_map(np.mean(got[f][:k], axis=0), refs[f]).mean()
                                              for f in evaluated])))
        for k, per_seed in by_k.items():
            row = {"method": method, "mode": f"average{k}", "rel_mse_per_seed": per_seed,
                   "mean": float(np.mean(per_seed)), "median": float(np.median(per_seed))}
            rows.append(row)
            print(f"{method:<28} {'mean of ' + str(k):<16} mean {row['mean']:.4f} median {row['median']:.4f}  "
                  f"per seed {' '.join(f'{e:.4f}' for e in per_seed)}", flush=True)
    load1 = os.getloadavg()[0]
    ref_mean = float(np.mean([ref_err[f] for f in evaluated]))
    print(f"{scene.name} {a.width}x{a.height}: load {load0:.1f} -> {load1:.1f}, {time.time() - t0:.0f} s; the "
          f"references' own relMSE (estimated) {ref_mean:.4f}")
    if a.out:
        Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        Path(a.out).write_text(json.dumps({
            "scene": scene.name, "width": a.width, "height": a.height, "frames": scene.frames,
            "evaluated": evaluated, "seeds": a.seeds, "load": [load0, load1], "reference_rel_mse": ref_mean,
            "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
