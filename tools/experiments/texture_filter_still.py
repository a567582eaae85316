"""F12's still of the textured scene (textured_room, 160x120) at equal time with each texture filter
(Settings.texture_filter: "full", what stills now read, and "mip", what they read before): relMSE against the
converged full-resolution image (what Cycles converges to) and against each filter's own converged image (its noise
alone), mean over seeds, and the samples each budget bought (docs/measurements/error-vs-time.md, "Texture filtering
of stills").

    python -m tools.experiments.texture_filter_still [BUDGET_S ...]
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.metrics import rel_mse
from restircl.scenes.textured import textured_room

REF = "/tmp/texture_filter_ref_{}_16k.npy"
REF_SAMPLES = 16384
SEEDS = (1, 2, 3)


def reference(scene, base: Settings, mode: str) -> np.ndarray:
    path = REF.format(mode)
    if not os.path.exists(path):
        r = Renderer(scene, replace(base, texture_filter=mode, seed=99))
        np.save(path, r.render_still(0, samples=REF_SAMPLES).color)
    return np.load(path)


def timed_still(scene, settings: Settings, budget_s: float) -> tuple[np.ndarray, int, float]:
    """(image, samples, seconds) of a still stopped once `budget_s` seconds have passed."""
    r = Renderer(scene, settings)
    r.render_still(0, samples=2)  # kernel build and warm-up
    t0 = time.perf_counter()
    f = r.render_still(0, samples=1 << 20, should_stop=lambda: time.perf_counter() - t0 > budget_s)
    return f.color, f.samples, time.perf_counter() - t0


def main() -> None:
    budgets = [float(a) for a in sys.argv[1:]] or [2.0, 8.0]
    scene = textured_room()
    base = still_settings(Settings(), scene)
    refs = {m: reference(scene, base, m) for m in ("full", "mip")}
    print(f"method {base.method}; mip reference vs full reference: relMSE {rel_mse(refs['mip'], refs['full']):.3e}")
    for budget in budgets:
        for mode in ("mip", "full"):
            rows = [timed_still(scene, replace(base, texture_filter=mode, seed=s), budget) for s in SEEDS]
            to_full = np.mean([rel_mse(img, refs["full"]) for img, _, _ in rows])
            to_own = np.mean([rel_mse(img, refs[mode]) for img, _, _ in rows])
            spp = np.mean([n for _, n, _ in rows])
            ms = np.mean([1e3 * s / n for _, n, s in rows])
            print(f"budget {budget:4.1f} s  {mode:4s}  samples {spp:6.1f}  ms/sample {ms:6.1f}  "
                  f"relMSE vs full {to_full:.3e}  vs own {to_own:.3e}", flush=True)


if __name__ == "__main__":
    main()
