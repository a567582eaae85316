"""Where TAA's own error (no noise: `taa_floor`'s converged modes) lies in the image, by pixel class, and how each
part of TAA moves it: docs/measurements/temporal-stability.md, "Where TAA's own error sits".

For one seed and the orbit's evaluated frames (4, 8, ..., 20, 23), TAA is fed the converged references
(`converged_input`: every frame; `converged_both`: the evaluated frame, with last frame's reference as its history)
under each variant (a method of `restircl report` with settings, `+key=value`, and optionally kernel defines after a
`|`, `;`-separated, e.g. `ris|TAA_CLIP_RADIUS=2`; the probes of the measurements, TAA_HISTORY_NEAREST, TAA_TAP_MIX,
TAA_CR_EDGES, TAA_EDGE_GAMMA, TAA_EDGE_ALPHA, TAA_BOX_HOLDS_SAMPLE, are in commit 0d9f874's opencl/taa/taa.cl, not in
the tree), and the per-pixel relMSE map is split over disjoint classes of pixels, taken in this order from the
frame's G-buffer and last frame's:

- `border`: within 2 pixels of the image's edge, or reprojected to within 1 pixel of it;
- `fresh`: no history (n = 1 after TAA: disoccluded or new);
- `edge`: a view-depth step above 5 % or a normal turn above 25 degrees to a 3x3 neighbour, or a miss beside a hit;
- `straddle`: not an edge, but the four bilinear history taps at its reprojected position are not all its surface
  (last frame's G-sample: the reprojection's depth and normal tests);
- `shadow`: not the above, but the reference's luminance changes by more than 2x within its 3x3 (a shadow's or a
  light pool's boundary on one surface);
- `glossy`: a lobe of roughness below 0.5 with a sampling weight above 0.05 (the surface's view-dependent look);
- `flat`: the rest (interior of a diffuse surface).

Mode `taa` is the animation as rendered (its noise in it); it also splits the error of the frame's own sample (no
TAA) by the same classes, and, where a variant is ReSTIR, each class's part in two by whether ReSTIR's temporal
pass found a history for the pixel (`nohist`: its reservoir after the temporal pass holds no more than the initial
candidates). `--seeds N` averages every figure over seeds seed .. seed + N - 1.

    python -m tools.experiments.taa_own_error --scene garden_orbit --variants "ris,ris+taa_filter=catmull_rom"
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np
from restircl.core import layouts as L
from restircl.core import program
from restircl.eval.metrics import rel_mse_map
from restircl.eval.probe_defines import parse_defines
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import motion_scene
from restircl.render.frame import read_image

from .restir_motion import orbit_arguments
from .taa_floor import _write_rgb, renderer

CLASSES = ("border", "fresh", "edge", "straddle", "shadow", "glossy", "flat")


def read_glossy(r, slot: int) -> np.ndarray | None:
    """(H, W) GLOSSY_SAMPLE records of history slot `slot`, None in a diffuse-only build."""
    buf = r.history.glossy(slot)
    if buf.size < r.width * r.height * L.GLOSSY_SAMPLE.itemsize:
        return None
    out = np.empty(r.width * r.height, L.GLOSSY_SAMPLE)
    import pyopencl as cl

    cl.enqueue_copy(r.device.queue, out, buf)
    r.device.queue.finish()
    return out.reshape(r.height, r.width)


def edge_mask(g: np.ndarray) -> np.ndarray:
    """Pixels with a depth step (> 5 %), a normal turn (> 25 deg) or a hit/miss change to a 3x3 neighbour."""
    depth, hit = g["pos"][..., 3], g["normal"][..., 3].view(np.int32) != -1
    n = g["normal"][..., :3]
    h, w = depth.shape
    out = np.zeros((h, w), bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx == dy == 0:
                continue
            ys, xs = np.clip(np.arange(h) + dy, 0, h - 1), np.clip(np.arange(w) + dx, 0, w - 1)
            d2, hit2, n2 = depth[ys][:, xs], hit[ys][:, xs], n[ys][:, xs]
            step = np.abs(d2 - depth) > 0.05 * np.minimum(np.abs(depth), np.abs(d2))
            turn = np.sum(n * n2, axis=-1) < np.cos(np.radians(25.0))
            out |= (hit != hit2) | (hit & hit2 & (step | turn))
    return out


def straddle_mask(g: np.ndarray, gp: np.ndarray, depth_tol: float = 0.1, normal_cos: float = 0.906) -> np.ndarray:
    """Pixels whose four bilinear history taps are not all their own surface in last frame's G-buffer `gp`."""
    h, w = g.shape
    m = g["motion"]
    has = m[..., 2] != 0.0
    px = np.arange(w)[None, :] + 0.5 + m[..., 0] - 0.5
    py = np.arange(h)[:, None] + 0.5 + m[..., 1] - 0.5
    x0, y0 = np.floor(np.nan_to_num(px)).astype(int), np.floor(np.nan_to_num(py)).astype(int)
    expected = m[..., 3]
    cur_hit = g["normal"][..., 3].view(np.int32) != -1
    out = np.zeros((h, w), bool)
    for t in range(4):
        tx, ty = x0 + (t & 1), y0 + (t >> 1)
        inside = (tx >= 0) & (ty >= 0) & (tx < w) & (ty < h)
        txc, tyc = np.clip(tx, 0, w - 1), np.clip(ty, 0, h - 1)
        pg = gp[tyc, txc]
        prev_hit = pg["normal"][..., 3].view(np.int32) != -1
        same_depth = np.abs(pg["pos"][..., 3] - expected) <= depth_tol * np.abs(expected)
        same_normal = np.sum(g["normal"][..., :3] * pg["normal"][..., :3], axis=-1) >= normal_cos
        same = (cur_hit == prev_hit) & (~cur_hit | (same_depth & same_normal))
        out |= inside & ~same
    return out & has


def glossy_mask(gl: np.ndarray | None, shape: tuple[int, int]) -> np.ndarray:
    if gl is None:
        return np.zeros(shape, bool)
    out = np.zeros(shape, bool)
    for lobe in ("lobe0", "lobe1"):
        alpha, weight = gl[lobe]["a"][..., 3], gl[lobe]["d"][..., 3]
        out |= (weight > 0.05) & (np.sqrt(np.maximum(alpha, 0.0)) < 0.5)
    return out


def light_edge_mask(ref: np.ndarray, ratio: float = 2.0) -> np.ndarray:
    """Pixels whose 3x3 neighbourhood in the reference spans more than `ratio` in luminance (plus 5 % of the image's
    mean, so that dark noise does not count)."""
    lum = ref[..., :3] @ np.array([0.2126, 0.7152, 0.0722]) + 0.05 * float(np.mean(ref[..., :3]))
    h, w = lum.shape
    lo, hi = lum.copy(), lum.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            ys, xs = np.clip(np.arange(h) + dy, 0, h - 1), np.clip(np.arange(w) + dx, 0, w - 1)
            lo, hi = np.minimum(lo, lum[ys][:, xs]), np.maximum(hi, lum[ys][:, xs])
    return hi > ratio * lo


def restir_no_history(r) -> np.ndarray | None:
    """(H, W) pixels whose reservoir after ReSTIR's temporal pass holds only this frame's candidates (no history
    reused); None for a method without reservoirs."""
    if getattr(r.settings, "method", "") != "restir" or not hasattr(r.buffers, "res_temp"):
        return None
    import pyopencl as cl

    temp = np.empty(r.width * r.height, L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, temp, r.buffers.res_temp)
    r.device.queue.finish()
    per_frame = r.settings.candidates + (r.last_plan.bsdf_candidates if r.last_plan else 0)
    fresh = (temp["M"] > 0) & (temp["M"] <= per_frame)  # M = 0: a miss, nothing to reuse
    return fresh.reshape(r.height, r.width)


def classify(g: np.ndarray, gp: np.ndarray, gl: np.ndarray | None, n: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """(H, W) index into CLASSES: the first class (in that order) a pixel is in."""
    h, w = g.shape
    m = g["motion"]
    yy, xx = np.mgrid[0:h, 0:w]
    px, py = xx + 0.5 + np.nan_to_num(m[..., 0]), yy + 0.5 + np.nan_to_num(m[..., 1])
    border = (xx < 2) | (yy < 2) | (xx >= w - 2) | (yy >= h - 2) | (px < 1) | (py < 1) | (px > w - 1) | (py > h - 1)
    masks = [border, n <= 1.0, edge_mask(g), straddle_mask(g, gp), light_edge_mask(ref), glossy_mask(gl, (h, w))]
    cls = np.full((h, w), len(CLASSES) - 1, int)
    for k in reversed(range(len(masks))):
        cls[masks[k]] = k
    return cls


def run_variant(scene, variant: str, seed: int, mode: str, refs: dict, evaluated: list[int]) -> dict:
    """{frame: (relMSE map, n, G-buffer, last frame's G-buffer, glossy records)} of TAA fed the references."""
    method, _, defines = variant.partition("|")
    base = program.kernel_defines
    extra = parse_defines([d for d in defines.split(";") if d])
    program.kernel_defines = lambda: {**base(), **extra}  # type: ignore[assignment]
    try:
        r = renderer(scene, method, seed)
        plain, now = r.taa.run, {"frame": 0}

        def run(state, moving):
            f, h = now["frame"], r.history
            if mode == "taa":  # the animation as rendered: its noise included
                return plain(state, moving)
            if mode == "converged_input" or f in evaluated:
                _write_rgb(r, r.buffers.sample, refs[f])
            if mode == "converged_both" and f in evaluated and h.valid:
                _write_rgb(r, h.taa[h.prev], refs[f - 1])
            return plain(state, moving)

        r.taa.run = run  # type: ignore[method-assign]
        out, last_g = {}, None
        for f in range(scene.frames):
            now["frame"] = f
            _, color, _ = r.run_frame(f, still=False)
            g = r.read_gbuffer().copy()
            if f in evaluated:
                img = read_image(r.device.queue, color, (r.height, r.width))[..., :3]
                raw = read_image(r.device.queue, r.sample_buf, (r.height, r.width))[..., :3]
                out[f] = (
                    rel_mse_map(img, refs[f]),
                    r.history_length().copy(),
                    g,
                    last_g,
                    read_glossy(r, r.history.cur),
                    rel_mse_map(raw, refs[f]),
                    restir_no_history(r),
                )
            last_g = g
        return out
    finally:
        program.kernel_defines = base  # type: ignore[assignment]


def class_parts(maps: dict, classes: dict, evaluated: list[int], within=None) -> dict[str, float]:
    """Each class's sum of the relMSE maps over all pixels (mean over the evaluated frames), optionally of the
    pixels of the masks `within` only."""
    out = {}
    for k, name in enumerate(CLASSES):
        out[name] = float(
            np.mean(
                [
                    maps[f][(classes[f] == k) & (True if within is None else within[f])].sum() / maps[f].size
                    for f in evaluated
                ]
            )
        )
    return out


def seed_rows(scene, a, refs: dict, evaluated: list[int], seed: int) -> list[dict]:
    """The rows of every mode and variant for one seed."""
    rows, classes = [], None
    for mode in [m for m in a.modes.split(",") if m]:
        for variant in [v for v in a.variants.split(",") if v]:
            got = run_variant(scene, variant, seed, mode, refs, evaluated)
            if classes is None:  # the G-buffers do not depend on the variant (same seed, same jitter)
                classes = {f: classify(g, gp, gl, n, refs[f]) for f, (_, n, g, gp, gl, _, _) in got.items()}
            taa = {f: got[f][0] for f in evaluated}
            row = {
                "variant": variant,
                "mode": mode,
                "rel_mse": float(np.mean([m.mean() for m in taa.values()])),
                "per_frame": [float(taa[f].mean()) for f in evaluated],
                "part": class_parts(taa, classes, evaluated),
                "pixels": {
                    c: float(np.mean([np.mean(classes[f] == k) for f in evaluated])) for k, c in enumerate(CLASSES)
                },
            }
            if mode == "taa":  # the frame's own sample, no TAA, by the same classes
                row["sample"] = class_parts({f: got[f][5] for f in evaluated}, classes, evaluated)
                nohist = {f: got[f][6] for f in evaluated}
                if all(v is not None for v in nohist.values()):
                    row["nohist_part"] = class_parts(taa, classes, evaluated, nohist)
                    row["nohist_sample"] = class_parts({f: got[f][5] for f in evaluated}, classes, evaluated, nohist)
                    row["nohist_pixels"] = {
                        c: float(np.mean([np.mean((classes[f] == k) & nohist[f]) for f in evaluated]))
                        for k, c in enumerate(CLASSES)
                    }
            rows.append(row)
    return rows


def mean_rows(per_seed: list[list[dict]]) -> list[dict]:
    """The rows averaged over the seeds (every number; dicts of numbers key by key)."""

    def avg(vals):
        if isinstance(vals[0], dict):
            return {k: avg([v[k] for v in vals]) for k in vals[0]}
        if isinstance(vals[0], list):
            return [avg(list(t)) for t in zip(*vals, strict=True)]
        return float(np.mean(vals)) if isinstance(vals[0], float) else vals[0]

    return [avg(list(rs)) for rs in zip(*per_seed, strict=True)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--variants", default="ris", help="comma-separated; kernel defines after '|', ';'-separated")
    ap.add_argument("--modes", default="converged_both,converged_input")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--seeds", type=int, default=1, help="seeds seed .. seed + seeds - 1, figures averaged")
    ap.add_argument("--ref-seconds", type=float, default=10.0)
    ap.add_argument("--cache-dir", default="out/refs")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    evaluated = sorted({*range(a.every, scene.frames, a.every), scene.frames - 1})
    refs = {
        f: get_reference(scene, f, a.ref_seconds, cache_dir=Path(a.cache_dir), log=lambda s: None).image
        for f in range(scene.frames)
    }
    t0, load0 = time.time(), os.getloadavg()[0]
    rows = mean_rows([seed_rows(scene, a, refs, evaluated, s) for s in range(a.seed, a.seed + a.seeds)])
    for row in rows:
        if "sample" in row:
            print(
                f"{'(its samples)':<16} {row['variant']:<44} relMSE {sum(row['sample'].values()):.4f}  "
                + "  ".join(f"{c} {row['sample'][c]:.4f}" for c in CLASSES)
            )
        print(
            f"{row['mode']:<16} {row['variant']:<44} relMSE {row['rel_mse']:.4f}  "
            + "  ".join(f"{c} {row['part'][c]:.4f} ({row['pixels'][c]:.1%})" for c in CLASSES)
        )
        if "nohist_part" in row:
            print(
                f"{'  no history':<16} {row['variant']:<44} relMSE {sum(row['nohist_part'].values()):.4f}  "
                + "  ".join(
                    f"{c} {row['nohist_part'][c]:.4f} ({row['nohist_pixels'][c]:.1%}; sample "
                    f"{row['nohist_sample'][c]:.4f})"
                    for c in CLASSES
                ),
                flush=True,
            )
    load1 = os.getloadavg()[0]
    print(
        f"{scene.name} {a.width}x{a.height} seeds {a.seed}..{a.seed + a.seeds - 1}: load {load0:.1f} -> "
        f"{load1:.1f}, {time.time() - t0:.0f} s (class parts: the class's sum of the map over all pixels)"
    )
    if a.out:
        Path(a.out).write_text(
            json.dumps(
                {
                    "scene": scene.name,
                    "seed": a.seed,
                    "seeds": a.seeds,
                    "evaluated": evaluated,
                    "load": [load0, load1],
                    "rows": rows,
                },
                indent=1,
            )
        )


if __name__ == "__main__":
    main()
