"""Where ReSTIR DI's biased merge (bias_correction "none") darkens: the stress suite's `contact` case at equal
frames, per pixel class: docs/measurements/temporal-stability.md, "The biased merge's darkening, by pixel class".

Each run is `frames` frames of the case's still camera from an empty history (one chain of history, unlike
render_still's two). After every frame the temporal pass's output is read back: a pixel whose reservoir there holds
no more than one frame's candidates found no history (fresh: the first frame, or a permuted neighbour that failed
the surface test). Frame 0 is its own class; after it, each pixel-frame is `fresh` or `history`, and the pixels
also fall in bands by their distance to the floor's edge (where the emitters stand), over the frames after
frame 0 (over frame 0 with --frames 1). For each method and class
this prints the relative bias sum(estimate - reference) / sum(reference) of the 1-sample images with its standard
error over the independent runs, and the share of pixel-frames in the class.

    python -m tools.experiments.biased_fresh --runs 16 --frames 16 \
        --methods none,none+perm,pairwise,pairwise+perm [--define NAME=VALUE]

A method is a bias correction, `+perm` for permutation sampling on (also for "none", which the renderer's
permutation_key otherwise leaves unpermuted) and `+key=value` for any other setting.
"""

from __future__ import annotations

import argparse
import math
import warnings

import numpy as np
import pyopencl as cl
from restircl.core import layouts as L
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.stress.catalog import cases
from restircl.eval.stress.judging import STILL_SETTINGS
from restircl.eval.stress.references import compute_reference, luminance
from restircl.render import stages
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings

_KEY = stages.permutation_key


def _permute_biased_too(settings, state, gi=False) -> int:  # noqa: ANN001
    """permutation_key without its exclusion of the biased merge (the experiment's `+perm` on "none")."""
    if settings.bias_correction == "none" and not gi and settings.temporal_permutation:
        key = int(state.frame_params["sample"]) * 0x9E3779B1 + int(state.frame_params["seed"]) * 0x85EBCA6B
        return 16 | ((key & 0xFFFFFFFF) >> 28)
    return _KEY(settings, state, gi)


def parse_method(spec: str) -> dict:
    parts = spec.split("+")
    out: dict = dict(method="restir", bias_correction=parts[0], temporal_permutation=False)
    for p in parts[1:]:
        if p == "perm":
            out["temporal_permutation"] = True
        else:
            k, v = p.split("=")
            out[k] = type(getattr(Settings(), k))(v) if not isinstance(getattr(Settings(), k), bool) else v == "1"
    return out


def bands(valid: np.ndarray) -> np.ndarray:
    """Per pixel its distance in pixels (Chebyshev) to the nearest pixel without a floor surface, capped at 4."""
    h, w = valid.shape
    d = np.full((h, w), 4)
    ys, xs = np.nonzero(~valid)
    for y in range(h):
        for x in range(w):
            if valid[y, x] and len(ys):
                d[y, x] = min(4, int(np.min(np.maximum(abs(ys - y), abs(xs - x)))))
    d[~valid] = -1
    return d


def run(case, ref, spec: str, runs: int, frames: int, seed: int) -> dict[str, np.ndarray]:  # noqa: ANN001
    """Per run and class: sums of the estimate's and the reference's luminance, and the pixel-frame counts."""
    settings = Settings(**{**STILL_SETTINGS, **case.settings, **parse_method(spec), "seed": seed})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = Renderer(case.scene, settings, None)
    lref = luminance(ref.mean)
    valid = lref > 0
    band = bands(valid)
    fresh_m = 0.0  # the M of a reservoir without history: every pixel's on frame 0
    classes = ["frame0", "fresh", "history"] + [f"band{b}" for b in range(5)]
    est = {c: np.zeros(runs) for c in classes}
    refs = {c: np.zeros(runs) for c in classes}
    count = {c: np.zeros(runs) for c in classes}
    res = np.empty(r.pixels, L.RESERVOIR)
    for k in range(runs):
        r.reset()
        r.settings.seed = seed + k
        for j in range(frames):
            f = r.render_frame(0, still=True, aovs=False)
            cl.enqueue_copy(r.device.queue, res, r.buffers.res_initial if j == 0 else r.buffers.res_temp)
            m = res["M"].reshape(r.height, r.width)
            lum = luminance(f.noisy.astype(np.float64))
            if j == 0:  # frame 0 has no temporal pass: its initial reservoirs' M
                fresh_m = float(m[valid].max())
            masks = {"frame0": valid if j == 0 else np.zeros_like(valid)}
            if j > 0:
                masks["fresh"] = valid & (m <= fresh_m)
                masks["history"] = valid & (m > fresh_m)
            if j > 0 or frames == 1:
                for b in range(5):
                    masks[f"band{b}"] = band == b
            for c, mk in masks.items():
                est[c][k] += lum[mk].sum()
                refs[c][k] += lref[mk].sum()
                count[c][k] += mk.sum()
    return dict(est=est, ref=refs, count=count)


def report(spec: str, out: dict) -> str:
    cells = []
    for c in out["est"]:
        e, rr, n = out["est"][c], out["ref"][c], out["count"][c]
        if rr.sum() <= 0:
            cells.append(f"{c} -")
            continue
        per_run = e - rr
        b = per_run.sum() / rr.sum()
        se = per_run.std(ddof=1) * math.sqrt(len(per_run)) / rr.sum()
        share = n.sum()
        cells.append(f"{c} {b:+.3f}+-{se:.3f} (n {int(share)})")
    return f"{spec:<28} " + " | ".join(cells)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", default="contact")
    ap.add_argument("--methods", default="none,none+perm,pairwise,pairwise+perm")
    ap.add_argument("--runs", type=int, default=16)
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--define", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    stages.permutation_key = _permute_biased_too
    case = cases(False, [a.case])[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = compute_reference(case, None)
    print(f"{a.case}: {a.runs} runs x {a.frames} frames, seed {a.seed}, defines {a.define}")
    for spec in a.methods.split(","):
        print(report(spec, run(case, ref, spec, a.runs, a.frames, a.seed)), flush=True)


if __name__ == "__main__":
    main()
