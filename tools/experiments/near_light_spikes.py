"""Where an orbit's relMSE spikes lie and how near a light they are: docs/measurements/temporal-stability.md, "What
ReSTIR's spikes on market_orbit at 640x360 are".

Renders the orbit through TAA, one frame per animation frame (restir_motion's `--equal-frames`), with each method and
seed, and prints every seed's relMSE per evaluated frame; then, per method, the relMSE split by the distance from the
pixel's G-buffer point to the nearest light's centre (bands in metres; each band's part of the relMSE, the mean and
the median over seeds and frames) and, with `--top`, each frame's largest terms (pixel, share of the frame's relMSE,
distance, TAA's n, the frame's sample luminance). `--trace LIGHT` (ReSTIR methods) compiles the kernel probe
PROBE_REUSE_LIGHT: the temporal and spatial passes print every merge whose input or result holds that light (the
history pixel taken, both reservoirs, both targets of each sample before any shadow test, the result and its shaded
value target x W; "sample" counts the frames rendered, the renderer's two warm-up frames included: animation frame +
2), and `--trace-weight W` adds PROBE_FLYFIRE's initial candidates whose weight exceeds W, so that a spike's sample
can be followed back to the candidate that drew it; `--until F` stops after animation frame F (the scene keeps
`--frames`, so its cached references still apply).

    python -m tools.experiments.near_light_spikes --scene market_orbit --width 640 --height 360 --ref-seconds 90 \\
        --cache-dir REFS --methods ris+candidates=20,restir --seeds 6 --top 3
"""

from __future__ import annotations

import argparse
import ctypes
from pathlib import Path

import numpy as np
from restircl.eval.metrics import rel_mse_map
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import motion_scene
from restircl.render.frame import read_image

from .restir_motion import orbit_arguments
from .taa_floor import renderer

LUMA = np.array([0.2126, 0.7152, 0.0722])
BANDS = (0.0, 0.3, 0.5, 1.0, np.inf)


def nearest_light(pos: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Distance from every point of `pos` (..., 3) to the nearest of `centres` (L, 3)."""
    flat = pos.reshape(-1, 3)
    d = np.full(len(flat), np.inf)
    for k in range(0, len(centres), 64):
        diff = flat[:, None, :] - centres[None, k : k + 64]
        d = np.minimum(d, np.sqrt((diff**2).sum(-1)).min(1))
    return d.reshape(pos.shape[:-1])


def render_seed(
    scene, method: str, seed: int, refs: dict[int, np.ndarray], until: int
) -> dict[int, dict[str, np.ndarray]]:
    """{evaluated frame: relMSE map, distance to the nearest light, TAA's n, the sample's luminance}, frames 0 ..
    `until` rendered."""
    r = renderer(scene, method, seed)
    centres = r.lights.records["p"][:, :3].astype(np.float64)
    shape = (r.height, r.width)
    got = {}
    for f in range(until + 1):
        _, color, _ = r.run_frame(f, still=False)
        ctypes.CDLL(None).fflush(None)  # a probe's printf lines before the next frame's
        if f not in refs:
            continue
        q = r.device.queue
        pos = r.read_gbuffer()["pos"].reshape(*shape, 4)[..., :3].astype(np.float64)
        got[f] = {
            "map": rel_mse_map(read_image(q, color, shape)[..., :3], refs[f]),
            "dist": nearest_light(pos, centres),
            "n": r.history_length(),
            "sample": read_image(q, r.sample_buf, shape)[..., :3] @ LUMA,
        }
    return got


def band_table(runs: list[dict[int, dict[str, np.ndarray]]]) -> list[str]:
    """Per distance band: its share of the pixels, its part of the relMSE (mean and median over seeds x frames)."""
    rows = []
    for lo, hi in zip(BANDS[:-1], BANDS[1:], strict=True):
        parts, frac = [], []
        for run in runs:
            for v in run.values():
                inside = (v["dist"] >= lo) & (v["dist"] < hi)
                parts.append(v["map"][inside].sum() / v["map"].size)
                frac.append(inside.mean())
        rows.append(
            f"[{lo:g}, {hi:g}) m, {100 * np.mean(frac):.1f} % of pixels: {np.mean(parts):.4f} "
            f"(median {np.median(parts):.4f})"
        )
    return rows


def top_terms(v: dict[str, np.ndarray], top: int) -> str:
    """The frame's `top` largest relMSE terms: pixel, share of the frame's relMSE, distance, n, sample luminance."""
    m = v["map"]
    ys, xs = np.unravel_index(np.argsort(m, axis=None)[::-1][:top], m.shape)
    return "; ".join(
        f"({x},{y}) {m[y, x] / m.size:.4f} d {v['dist'][y, x]:.2f} m n {v['n'][y, x]:.0f} "
        f"sample {v['sample'][y, x]:.1f}"
        for y, x in zip(ys, xs, strict=True)
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--methods", default="ris+candidates=20,restir")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--top", type=int, default=0, help="print each frame's largest terms")
    ap.add_argument("--trace", type=int, default=-1, help="light whose reuse merges the kernels print")
    ap.add_argument("--trace-weight", type=float, default=0.0, help="print initial candidates above this weight")
    ap.add_argument("--until", type=int, default=-1, help="last animation frame rendered (-1: all)")
    ap.add_argument("--ref-seconds", type=float, default=10.0)
    ap.add_argument("--cache-dir", default="out/refs")
    a = ap.parse_args()
    if a.trace >= 0:
        add_probe_defines([f"PROBE_REUSE_LIGHT={a.trace}"])
    if a.trace_weight > 0:
        add_probe_defines([f"PROBE_FLYFIRE={a.trace_weight!r}"])
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    until = scene.frames - 1 if a.until < 0 else min(a.until, scene.frames - 1)
    evaluated = [f for f in sorted({*range(a.every, scene.frames, a.every), scene.frames - 1}) if f <= until]
    refs = {
        f: get_reference(scene, f, a.ref_seconds, cache_dir=Path(a.cache_dir), log=lambda s: None).image[..., :3]
        for f in evaluated
    }
    for method in a.methods.split(","):
        runs = []
        for seed in range(a.first_seed, a.first_seed + a.seeds):
            print(f"{method} seed {seed}", flush=True)
            run = render_seed(scene, method, seed, refs, until)
            runs.append(run)
            per = [v["map"].mean() for v in run.values()]
            print(
                f"  relMSE {np.mean(per):.4f}; per frame "
                + " ".join(f"{f}: {x:.4f}" for f, x in zip(run, per, strict=True))
            )
            for f, v in run.items() if a.top else ():
                print(f"  frame {f}: {top_terms(v, a.top)}")
        seeds = [np.mean([v["map"].mean() for v in run.values()]) for run in runs]
        print(
            f"{method}: relMSE mean {np.mean(seeds):.4f}, median {np.median(seeds):.4f}; by distance to the "
            "nearest light:"
        )
        for row in band_table(runs):
            print("  " + row)


if __name__ == "__main__":
    main()
