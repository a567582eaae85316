"""The environment's sampling table on F12's still path (docs/error-vs-time.md, the 2026-12-04 sky note): the
held-out `sky` kind at 192x108, rendered as F12 renders it (`still_settings` through `ours_settings("auto")`), with
the alias table and with the cumulative one (lights/environment.TABLE_KIND), relMSE against the cached 2 x 1024-spp
Cycles reference at 64 and 256 frames, and ms per frame (wall and CPU of all threads). Needs bpy and the reference
(`restircl compare --kinds sky` caches it).

    python tools/sky_table_kinds.py [--rounds 2] [--seeds 7,8,9]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

from restircl.eval import cycles
from restircl.eval.cycles_compare import HEIGHT, REFERENCE_SPP, WIDTH, cycles_reference, ours_settings
from restircl.eval.held_out import held_out
from restircl.eval.metrics import rel_mse
from restircl.lights import environment
from restircl.pipeline import Renderer


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--seeds", default="7,8,9")
    a = ap.parse_args()
    scene = held_out("sky", WIDTH, HEIGHT)
    ref = cycles_reference("sky", scene, cycles.to_bpy(scene), REFERENCE_SPP, 2, None, print)
    for rnd in range(a.rounds):
        for kind in ("alias", "cdf"):
            environment.TABLE_KIND = kind  # the packed map is keyed by the kind: each is built once
            for seed in (int(s) for s in a.seeds.split(",")):
                r = Renderer(scene, replace(ours_settings("auto", scene), seed=seed))
                r.render_still(0, 2)  # warm-up: program build, upload
                for n in (64, 256):
                    t0, c0 = time.perf_counter(), time.process_time()
                    img = r.render_still(0, n).color[..., :3]
                    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
                    print(f"round {rnd} {kind:5} seed {seed} n {n:4}: relMSE {rel_mse(img, ref.image):.3e}  "
                          f"{wall * 1e3 / n:6.2f} ms/frame wall {cpu * 1e3 / n:6.2f} CPU", flush=True)
                got = r.device_scene.lights.environment
                assert got is not None and got.kind == kind, "the table kind did not reach the device"


if __name__ == "__main__":
    main()
