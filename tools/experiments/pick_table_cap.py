"""The per-pixel light pick of stills (lights/pick_table.py) beyond 16 lights: F12's still path with the table's
cap (MAX_LIGHTS) at 16 (the cap before: the candidates come from the light array above it) and at `--cap`, at equal
samples, relMSE against our own converged image (eval/report/reference.py, cached) and the CPU seconds of the
frames (time.process_time: the machine is shared). relMSE x CPU seconds compares at equal time (lower is better).

Tuning scenes: the tuning garden with fewer lights (`garden:N`, eval/scenes/held_out.py garden(lights=N)).
Validation: the `user` kind (43 lights and an HDRI world, eval/scenes/user_scene.py), measured once after the choice.

    python -m tools.experiments.pick_table_cap --scenes garden:24,garden:48 --cap 64 --samples 64,256
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from restircl.eval.metrics import rel_mse
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes import held_out
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.lights import pick_table
from restircl.render.pipeline import Renderer
from restircl.render.still_method import still_settings
from restircl.scene.scene import Scene
from restircl.settings.table import Settings

DEVICE_MAX = pick_table.MAX_LIGHTS  # PICK_TABLE_MAX of the device's arrays (the cap below is the host's rule)


def scene_of(name: str) -> Scene:
    kind, _, n = name.partition(":")
    if kind == "garden" and n:
        s = held_out.garden(held_out.WIDTH, held_out.HEIGHT, lights=int(n)).validate()
        s.name = f"garden{n}"
        return s
    return scene_of_kind(kind)


def run(name: str, cap: int, samples: list[int], seeds: int, ref_seconds: float, cache: Path) -> None:
    scene = scene_of(name)
    ref = get_reference(scene, 0, ref_seconds, cache_dir=cache, log=lambda s: None)
    print(f"{name}: {len(scene.lights)} lights, reference {ref.method} {ref.frames} frames, "
          f"its relMSE {ref.est_rel_mse:.2e}", flush=True)
    got: dict[str, list[tuple[float, float, int]]] = {}
    for seed in range(seeds):
        for n in samples:
            for label, limit in (("array (cap 16)", 16), (f"table (cap {cap})", cap)):
                pick_table.MAX_LIGHTS = limit
                r = Renderer(scene, still_settings(replace(Settings(), seed=7 + seed), scene))
                r.render_still(0, 1)  # program build, upload
                c0 = time.process_time()
                img = r.render_still(0, n).color[..., :3]
                cpu = time.process_time() - c0
                got.setdefault(label, []).append((rel_mse(img, ref.image), cpu, n))
                print(f"{name} {label:15} n {n:4} seed {seed}: relMSE {got[label][-1][0]:.3e}, "
                      f"{cpu * 1e3 / n:.2f} CPU ms per frame", flush=True)
    pick_table.MAX_LIGHTS = DEVICE_MAX
    for n in samples:
        base = None
        for label, rows in got.items():
            e = float(np.mean([r[0] for r in rows if r[2] == n]))
            cpu = float(np.mean([r[1] for r in rows if r[2] == n]))
            base = base or e * cpu
            print(f"| {name} | {label} | {n} | {e:.3e} | {cpu * 1e3 / n:.2f} | {e * cpu / base:.2f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default="garden:24,garden:48")
    ap.add_argument("--cap", type=int, default=64)
    ap.add_argument("--samples", default="64,256")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--ref-seconds", type=float, default=60.0)
    ap.add_argument("--cache-dir", default="out/refs")
    a = ap.parse_args()
    assert a.cap <= DEVICE_MAX, "the table kernel's arrays hold PICK_TABLE_MAX = pick_table.MAX_LIGHTS lights"
    print(f"load average {os.getloadavg()[0]:.2f}")
    for name in a.scenes.split(","):
        run(name, a.cap, [int(n) for n in a.samples.split(",")], a.seeds, a.ref_seconds, Path(a.cache_dir))
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
