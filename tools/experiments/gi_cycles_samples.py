"""Cycles' relMSE per sample on a kind with bounces (the other side of tools/experiments/gi_variance.py): Cycles at
a fixed sample count over a few seeds against the kind's cached reference, with its seconds per sample. Only for
tuning scenes.

    python -m tools.experiments.gi_cycles_samples --kind gi_tuning_room --samples 32 --seeds 3
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import numpy as np
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.metrics import rel_mse, rel_mse_map
from restircl.eval.scenes.kinds import scene_of_kind

from .gi_agreement import material_map
from .gi_variance import reference


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--kind", default="gi_tuning_room")
    p.add_argument("--max-bounces", type=int, default=4)
    p.add_argument("--samples", type=int, default=32)
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--cache-dir", default="out/cache")
    a = p.parse_args()
    if a.kind in ("interior", "outdoor"):
        raise SystemExit("interior and outdoor are validation scenes: tune on gi_tuning_room")
    paths = LightPaths.of(a.max_bounces)
    ref = reference(a.kind, paths, Path(a.cache_dir))
    scene = scene_of_kind(a.kind)
    sc = cycles.to_bpy(scene)
    cycles.render(sc, samples=1, threads=2, paths=paths.cycles())
    errs, secs, maps = [], [], []
    for seed in range(a.seeds):
        res = cycles.render(sc, samples=a.samples, seed=200 + seed, threads=2, paths=paths.cycles())
        errs.append(rel_mse(res.image, ref))
        secs.append(res.render_seconds / a.samples)
        maps.append(rel_mse_map(res.image, ref))
    mats, mean_map = material_map(scene), np.mean(maps, axis=0)
    print(f"cycles {a.samples} spp relMSE {np.mean(errs):.3e} ({', '.join(f'{e:.2e}' for e in errs)}) "
          f"{np.median(secs) * 1e3:6.1f} ms/spp (render only)  load {os.getloadavg()[0]:.1f}")
    print("    " + "  ".join(f"{m.name} {mean_map[mats == i].sum() / mean_map.size:.1e}"
                             for i, m in enumerate(scene.materials) if (mats == i).any()))


if __name__ == "__main__":
    main()
