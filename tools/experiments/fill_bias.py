"""How bright TAA's fresh pixels come out against the reference on an orbiting camera: docs/measurements/
temporal-stability.md, "The fill's mean and outliers".

The pixels that start their history on a frame (n = 1 in TAA's output: disoccluded, new at the border, and the
fill's pixels among them) are where the fill (opencl/taa/fresh_fill.h) acts. Over the evaluated frames after frame 0
and the seeds, this prints for each method their share of the image, the sum of their luminance over the
reference's at them (1 is unbiased; a robust mean that darkens bright sparse lights shows below it), and their part
of the frame's relMSE (the sum of their per-pixel relMSE terms over all pixels) beside the other pixels' part.

    python -m tools.experiments.fill_bias --scene garden_orbit --methods ris+candidates=20,restir --seeds 4 \
        --cache-dir /tmp/fill/refs [--define TAA_FRESH_FILL_ROBUST=0]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pyopencl as cl
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.moving import _warm_renderer
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.motion_validation import motion_scene

from .restir_motion import orbit_arguments


def luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--methods", default="ris+candidates=20,restir")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--ref-seconds", type=float, default=10.0)
    ap.add_argument("--cache-dir", default="out/refs")
    ap.add_argument("--define", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    evaluated = sorted({*range(0, scene.frames, a.every), scene.frames - 1})
    refs = {f: get_reference(scene, f, a.ref_seconds, cache_dir=Path(a.cache_dir), log=lambda s: None).image
            .astype(np.float64) for f in evaluated}
    print(f"{scene.name} {a.width}x{a.height} {a.define}: fresh pixels (n = 1) over frames {evaluated[1:]}, "
          f"{a.seeds} seeds")
    print(f"{'method':<40} {'share':>6} {'lum / ref':>9} {'per seed':>28} {'relMSE fresh':>12} {'other':>7}")
    for m in a.methods.split(","):
        ratios, share, e_fresh, e_other = [], [], [], []
        for seed in range(1, a.seeds + 1):
            r = _warm_renderer(scene, m, None, None, seed, still=False)
            lum, lum_ref = 0.0, 0.0
            for j in range(scene.frames):
                color_buf = r.run_frame(j, still=False).color
                if j == 0 or j not in refs:
                    continue
                out = np.empty((r.height, r.width, 4), np.float32)
                cl.enqueue_copy(r.device.queue, out, color_buf)
                ref = refs[j][..., :3]
                fresh = out[..., 3] == 1.0
                img = out[..., :3].astype(np.float64)
                lum += float(luminance(img[fresh]).sum())
                lum_ref += float(luminance(ref[fresh]).sum())
                term = np.mean((img - ref) ** 2 / (ref * ref + 0.01), axis=2)
                share.append(float(fresh.mean()))
                e_fresh.append(float(term[fresh].sum() / term.size))
                e_other.append(float(term[~fresh].sum() / term.size))
            ratios.append(lum / lum_ref)
        print(f"{m:<40} {np.mean(share):>6.3f} {np.mean(ratios):>9.3f} "
              f"{' '.join(f'{x:.3f}' for x in ratios):>28} {np.mean(e_fresh):>12.4f} {np.mean(e_other):>7.4f}",
              flush=True)


if __name__ == "__main__":
    main()
