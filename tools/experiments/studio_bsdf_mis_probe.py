"""Tuning studio, F12's path against the same with the BSDF MIS sample (whose direction now comes from the Sobol
sequence) and with 1 candidate: relMSE against the cached Cycles reference at 128 and 512 frames, CPU ms per frame
(docs/measurements/error-vs-time.md, "A world alone: one candidate", last paragraph). Needs bpy and the reference.

    python -m tools.experiments.studio_bsdf_mis_probe
"""

from __future__ import annotations

import time
from dataclasses import replace

from restircl import Renderer, Settings, still_settings
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.compare import REFERENCE_SPP, cycles_reference
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH, held_out

VARIANTS = {"auto": {}, "auto+mis": {"bsdf_mis_sample": True}, "auto c1": {"candidates": 1}}


def main() -> None:
    scene = held_out("studio", WIDTH, HEIGHT)
    ref = cycles_reference("studio", scene, cycles.to_bpy(scene), REFERENCE_SPP, 2, None, print).image
    for rnd in range(2):
        for name, kw in VARIANTS.items():
            for seed in (7, 8):
                s = still_settings(replace(Settings(**kw), seed=seed), scene)
                r = Renderer(scene, s)
                r.render_still(0, 2)  # warm-up: program build, upload
                for n in (128, 512):
                    c0 = time.process_time()
                    img = r.render_still(0, n).color[..., :3]
                    cpu = time.process_time() - c0
                    print(f"round {rnd} {name:9} seed {seed} n {n}: relMSE {rel_mse(img, ref):.3e}, "
                          f"{cpu * 1e3 / n:.2f} CPU ms/frame [{s.candidates} candidates, BSDF MIS sample "
                          f"{s.bsdf_mis_sample}]", flush=True)


if __name__ == "__main__":
    main()
