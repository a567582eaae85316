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

A method is a bias correction, `+perm` for permutation sampling on and `+key=value` for any other setting.

With --orbit SCENE (garden_orbit, market_orbit: eval/scenes/motion_validation.py) it renders that orbit instead, as
tools/experiments/restir_motion.py does (TAA on, one frame per animation frame), and prints per method the image's
relative bias over the evaluated frames after frame 0, of ReSTIR's 1-sample image (noisy) and of TAA's output, and
the noisy image's bias over the pixels that found no ReSTIR history (fresh) and the others, per seed; methods are
then `restircl report` names (`restir+bias_correction=none`). With --cpu-orbit SCENE it times instead the CPU ms per
frame of each method built as it is and with TEST_BIASED_PLAIN_M (the plain 1/M), two renderers in one process,
their frames interleaved in blocks of the orbit's frames 2-23, `--seeds` times.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl.core import layouts as L
from restircl.core import program
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.moving import _warm_renderer
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import motion_scene
from restircl.eval.stress.catalog import cases
from restircl.eval.stress.judging import STILL_SETTINGS
from restircl.eval.stress.references import compute_reference, luminance
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings


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


def orbit(name: str, methods: list[str], seeds: int, cache_dir: str = "out/refs") -> None:
    """The orbit's relative bias per method: noisy and TAA images, and the noisy image's fresh and history pixels."""
    scene = motion_scene(name, 192, 108, 24)
    evaluated = sorted({*range(4, scene.frames, 4), scene.frames - 1})
    refs = {
        f: luminance(
            get_reference(scene, f, 10.0, cache_dir=Path(cache_dir), log=lambda s: None)
            .image[..., :3]
            .astype(np.float64)
        )
        for f in evaluated
    }
    print(f"{name}: relative bias over frames {evaluated}, per seed 1..{seeds}")
    for m in methods:
        sums = np.zeros((seeds, 4, 2))  # noisy, TAA, noisy fresh, noisy history; (estimate, reference)
        for k in range(seeds):
            r = _warm_renderer(scene, m, None, None, k + 1, still=False)
            res = np.empty(r.pixels, L.RESERVOIR)
            fresh_m = 0.0
            for j in range(scene.frames):
                _, color_buf, _ = r.run_frame(j, still=False)
                cl.enqueue_copy(r.device.queue, res, r.buffers.res_initial if j == 0 else r.buffers.res_temp)
                mres = res["M"].reshape(r.height, r.width)
                if j == 0:
                    fresh_m = float(mres.max())
                if j not in refs:
                    continue
                taa = np.empty((r.height, r.width, 4), np.float32)
                noisy = np.empty((r.height, r.width, 4), np.float32)
                cl.enqueue_copy(r.device.queue, taa, color_buf)
                cl.enqueue_copy(r.device.queue, noisy, r.buffers.sample)
                ln, lt, lr = (
                    luminance(noisy[..., :3].astype(np.float64)),
                    luminance(taa[..., :3].astype(np.float64)),
                    refs[j],
                )
                fresh = (mres <= fresh_m) & (mres > 0)
                for c, (x, mk) in enumerate([(ln, None), (lt, None), (ln, fresh), (ln, mres > fresh_m)]):
                    sel = np.ones_like(lr, bool) if mk is None else mk
                    sums[k, c] += (x[sel].sum(), lr[sel].sum())
        rel = sums[..., 0] / sums[..., 1] - 1.0
        cells = [
            f"{c} {rel[:, i].mean():+.4f} ({' '.join(f'{v:+.3f}' for v in rel[:, i])})"
            for i, c in enumerate(["noisy", "taa", "fresh", "history"])
        ]
        print(f"{m:<56} " + " | ".join(cells), flush=True)


def cpu_orbit(name: str, methods: list[str], repeats: int) -> None:
    """CPU ms per frame of each method as built and with the plain 1/M, interleaved in one process."""
    scene = motion_scene(name, 192, 108, 24)
    base = program.kernel_defines
    for m in methods:
        rs = {}
        for label, extra in (("targets", {}), ("plain_m", {"TEST_BIASED_PLAIN_M": True})):
            program.kernel_defines = (lambda e: lambda: {**base(), **e})(extra)
            rs[label] = _warm_renderer(scene, m, None, None, 1, still=False)
        program.kernel_defines = base
        cpu: dict[str, list[float]] = {k: [] for k in rs}
        for _ in range(repeats):
            for k, r in rs.items():
                for f in range(2, scene.frames):
                    c0 = time.process_time()
                    r.run_frame(f, still=False)
                    r.device.queue.finish()
                    cpu[k].append((time.process_time() - c0) * 1e3)
        med = {k: float(np.median(v)) for k, v in cpu.items()}
        print(
            f"{name} {m}: CPU ms per frame (median of {len(cpu['targets'])}) targets {med['targets']:.2f}, plain 1/M "
            f"{med['plain_m']:.2f}, ratio {med['targets'] / med['plain_m']:.3f}",
            flush=True,
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", default="contact")
    ap.add_argument("--methods", default="none,none+perm,pairwise,pairwise+perm")
    ap.add_argument("--runs", type=int, default=16)
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--seed", type=int, default=1000)
    ap.add_argument("--define", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--orbit", default=None, help="an orbit (192x108, 24 frames, every 4th evaluated) instead")
    ap.add_argument("--cpu-orbit", default=None, help="CPU time against the plain 1/M on an orbit instead")
    ap.add_argument("--seeds", type=int, default=4, help="--orbit: seeds 1 .. seeds; --cpu-orbit: repeats")
    ap.add_argument("--cache-dir", default="out/refs", help="--orbit: the references' cache")
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    if a.cpu_orbit:
        cpu_orbit(a.cpu_orbit, a.methods.split(","), a.seeds)
        return
    if a.orbit:
        orbit(a.orbit, a.methods.split(","), a.seeds, a.cache_dir)
        return
    case = cases(False, [a.case])[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = compute_reference(case, None)
    print(f"{a.case}: {a.runs} runs x {a.frames} frames, seed {a.seed}, defines {a.define}")
    for spec in a.methods.split(","):
        print(report(spec, run(case, ref, spec, a.runs, a.frames, a.seed)), flush=True)


if __name__ == "__main__":
    main()
