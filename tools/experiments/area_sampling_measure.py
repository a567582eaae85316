"""Area against solid-angle light sampling (setting area_sampling) on the tuning scenes of issue 23, measured
against the cached Cycles references of `restircl compare` (pass --cache-dir; nothing is rendered in Cycles):
relMSE at equal frames (per seed, with the seconds of the same render) and at equal wall time (budgets). The
reference is the cache's one image of the kind at 192x108 (its key, the scene file's digest, changes with the file
format even where the scene does not; the area-sampling RIS figure at 64 frames against
docs/measurements/error-vs-time.md's is the check that it still fits).

    python -m tools.experiments.area_sampling_measure --cache-dir /work/cache-compare23/refs --kinds studio,neon
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.cycles.compare import time_ours
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH, held_out

METHODS = {"ris": {"method": "ris"}, "default": {}}


def measure(kind: str, modes: list[str], methods: list[str], frames: int, seeds: int, budgets: list[float],
            cache_dir: Path) -> list[dict]:
    scene = held_out(kind)
    (path,) = sorted(cache_dir.glob(f"cycles_reference_{kind}_{WIDTH}x{HEIGHT}_2x1024_*.npy"))
    ref = np.load(path)
    rows = []
    for m in methods:
        for mode in modes:
            Renderer(scene, Settings(**METHODS[m], area_sampling=mode), None).render_still(0, 2)  # compile
    for seed in range(seeds):  # interleaved, so a change of load spreads over the modes
        for m in methods:
            for mode in modes:
                r = Renderer(scene, Settings(**METHODS[m], area_sampling=mode, seed=100 + seed).validate(), None)
                t0 = time.perf_counter()
                img = r.render_still(0, frames).color[..., :3]
                secs = time.perf_counter() - t0
                rows.append(dict(kind=kind, method=m, mode=mode, seed=seed, frames=frames, seconds=secs,
                                 rel_mse=rel_mse(img, ref)))
                print(json.dumps(rows[-1]), flush=True)
            for budget in budgets:
                for mode in modes:
                    s = Settings(**METHODS[m], area_sampling=mode, seed=200 + seed).validate()
                    img, secs, _, spp = time_ours(scene, s, budget)
                    rows.append(dict(kind=kind, method=m, mode=mode, seed=seed, budget=budget, frames=spp,
                                     seconds=secs, rel_mse=rel_mse(img, ref)))
                    print(json.dumps(rows[-1]), flush=True)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cache-dir", type=Path, required=True)
    ap.add_argument("--kinds", default="studio,neon")
    ap.add_argument("--modes", default="area,solid_angle,auto")
    ap.add_argument("--methods", default="ris,default")
    ap.add_argument("--frames", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--budgets", default="4")
    ap.add_argument("--out", type=Path)
    a = ap.parse_args()
    rows = []
    for kind in a.kinds.split(","):
        rows += measure(kind, a.modes.split(","), a.methods.split(","), a.frames, a.seeds,
                        [float(b) for b in a.budgets.split(",") if b], a.cache_dir)
    if a.out:
        a.out.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
