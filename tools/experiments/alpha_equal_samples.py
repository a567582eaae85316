"""Error at equal samples, ours on the alpha scene (eval/scenes/alpha_cards.py), against the Cycles reference that
alpha_equal_time.py leaves in ALPHA_REFERENCE (2 x 4096 spp): relMSE per render and times the samples (the
per-sample error, which the load does not change), and CPU seconds per sample (time.process_time, the process's
threads together). Run once per state of the code, PYTHONPATH at its tree:

    ALPHA_REFERENCE=ref.npy PYTHONPATH=python python tools/experiments/alpha_equal_samples.py [samples [seeds]]
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.scenes.alpha_cards import alpha_cards


def rel_mse(a: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((a - ref) ** 2 / (ref * ref + 1e-2)))


def main() -> None:
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 4
    refs = np.load(os.environ["ALPHA_REFERENCE"])
    ref = 0.5 * (refs[0] + refs[1])
    h, w = ref.shape[:2]
    scene = alpha_cards(w, h)
    errs, cpu = [], []
    for seed in range(1, seeds + 1):
        r = Renderer(scene, still_settings(Settings(seed=seed), scene))
        r.render_still(0, samples=1)  # compile
        t0 = time.process_time()
        img = r.render_still(0, samples=samples).color[..., :3]
        cpu.append((time.process_time() - t0) / samples)
        errs.append(rel_mse(img, ref))
    print(f"{w}x{h}, {samples} samples, seeds 1-{seeds}: relMSE mean {np.mean(errs):.3e} "
          f"(each {' '.join(f'{e:.2e}' for e in errs)}), x samples {np.mean(errs) * samples:.3e}; "
          f"CPU {1e3 * np.mean(cpu):.2f} ms per sample; load {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
