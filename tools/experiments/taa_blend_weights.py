"""What the noise-aware TAA blend (opencl/taa/blend_weight.h, Settings.taa_noise_blend) does per estimator on an
orbit: docs/measurements/temporal-stability.md, "A noise-aware TAA blend". For each method (rendered with the blend
on), over the frames from `--from` on and the pixels with a history of 8 frames or more: the mean weight a the blend
took, the share of pixels above alpha_min and above 0.3, and the median of the sample variance v_s the blend
estimated, relative to the squared sample luminance (the moments history's y).

    python -m tools.experiments.taa_blend_weights --scene garden_orbit --methods ris+candidates=20,restir
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from restircl.eval.report.methods import method_settings
from restircl.eval.scenes.motion_validation import motion_scene
from restircl.render.frame import read_image
from restircl.render.pipeline import Renderer

from .restir_motion import orbit_arguments


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    orbit_arguments(ap)
    ap.add_argument("--methods", default="ris+candidates=20,restir")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--from", dest="first", type=int, default=8, help="the first frame counted")
    a = ap.parse_args()
    scene = motion_scene(a.scene, a.width, a.height, a.frames)
    print(f"{scene.name} {a.width}x{a.height}, frames {a.first}-{scene.frames - 1}, load {os.getloadavg()[0]:.1f}")
    for method in a.methods.split(","):
        settings = method_settings(f"{method}+taa_noise_blend=true", None, a.seed)
        r = Renderer(scene, settings)
        for _ in range(2):  # warm-up (kernels compile at their first launch); then start without history
            r.run_frame(0, still=False)
        r.reset()
        weights, rel_var = [], []
        for f in range(scene.frames):
            r.run_frame(f, still=False)
            if f < a.first:
                continue
            mom = read_image(r.device.queue, r.history.taa_moments(r.history.prev, True), (r.height, r.width))
            old = r.history_length() >= 8
            weights.append(mom[..., 3][old])
            rel_var.append(mom[..., 1][old] / np.maximum(mom[..., 0][old] ** 2, 1e-4))
        w, v = np.concatenate(weights), np.concatenate(rel_var)
        floor = settings.alpha_min + 1e-3
        print(f"{method:<24} mean a {w.mean():.3f}, above alpha_min {np.mean(w > floor):.1%}, above 0.3 "
              f"{np.mean(w > 0.3):.1%}; median v_s / y^2 {np.median(v):.3f}", flush=True)


if __name__ == "__main__":
    main()
