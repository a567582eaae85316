"""F12's still of one light object (cornell_box 128x128): relMSE after 64 frames against a 2048-frame exhaustive
reference, mean over 4 seeds, and the median seconds per 64-frame still. Run it with PYTHONPATH of each checkout
to compare them (docs/measurements/error-vs-time.md, "One light").

    python -m tools.experiments.one_light_still NAME [CANDIDATES]
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.metrics import rel_mse
from restircl.scenes.builtin import cornell_box

REF = "/tmp/one_light_ref.npy"


def main() -> None:
    scene = cornell_box(128, 128)
    base = still_settings(Settings(), scene)
    if len(sys.argv) > 2:
        base = replace(base, candidates=int(sys.argv[2]))
    if not os.path.exists(REF):
        r = Renderer(scene, replace(base, method="reference", seed=99))
        np.save(REF, r.render_still(0, samples=2048).color)
    ref = np.load(REF)
    errs, secs = [], []
    for seed in (1, 2, 3, 4):
        r = Renderer(scene, replace(base, seed=seed))
        r.render_still(0, samples=2)  # kernel build and warm-up
        t = time.perf_counter()
        img = r.render_still(0, samples=64).color
        secs.append(time.perf_counter() - t)
        errs.append(rel_mse(img, ref))
    print(f"{sys.argv[1]} {base.method} {base.candidates} {base.sampler} relMSE {np.mean(errs):.3e} "
          f"{[f'{e:.2e}' for e in errs]} s {np.median(secs):.3f}", flush=True)


if __name__ == "__main__":
    main()
