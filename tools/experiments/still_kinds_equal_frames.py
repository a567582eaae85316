"""F12's still path on tuning kinds at equal frames: relMSE against the cached 2 x 1024-spp Cycles reference at
128 and 512 frames, seeds 7 and 8, and CPU ms per frame (docs/measurements/error-vs-time.md, "A light candidate as
one Sobol point"). Run it with PYTHONPATH at another checkout's python/ for the before side. Needs bpy and the
references.

    python -m tools.experiments.still_kinds_equal_frames studio,garden,neon,sky
"""

from __future__ import annotations

import sys
import time
from dataclasses import replace

from restircl import Renderer, Settings, still_settings
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.compare import REFERENCE_SPP, cycles_reference
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH, held_out


def main() -> None:
    for kind in sys.argv[1].split(","):
        scene = held_out(kind, WIDTH, HEIGHT)
        ref = cycles_reference(kind, scene, cycles.to_bpy(scene), REFERENCE_SPP, 2, None, lambda *a: None).image
        for seed in (7, 8):
            r = Renderer(scene, still_settings(replace(Settings(), seed=seed), scene))
            r.render_still(0, 2)  # warm-up: program build, upload
            for n in (128, 512):
                c0 = time.process_time()
                img = r.render_still(0, n).color[..., :3]
                cpu = time.process_time() - c0
                print(f"{kind:7} seed {seed} n {n}: relMSE {rel_mse(img, ref):.3e} {cpu * 1e3 / n:.2f} CPU ms",
                      flush=True)


if __name__ == "__main__":
    main()
