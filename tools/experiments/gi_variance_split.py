"""How the variance per sample of F12's still path splits between the direct light and each further bounce, on a
tuning scene (tools/experiments/gi_variance.py measures the error against Cycles' reference): the relMSE that the
spread over seeds gives (per pixel the variance of the N-sample image over the seeds, relative to the reference's
square + 0.01, as rel_mse; the seeds' mean where the kind has no Cycles reference), at Max Bounces 0, 1, 2 and 4,
so that each bounce's added variance shows; with the worst 0.1 % of pixels' share (fireflies). --overrides: Settings
fields as JSON (e.g. '{"path_light_pick": "array"}').

    python -m tools.experiments.gi_variance_split --kind gi_tuning_room --samples 32 --seeds 4
"""

from __future__ import annotations

import argparse
import os
from dataclasses import replace
from pathlib import Path

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render.still_method import still_settings

from .gi_agreement import material_map
from .gi_variance import reference


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--kind", default="gi_tuning_room")
    p.add_argument("--samples", type=int, default=32)
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--bounces", default="0,1,2,4")
    p.add_argument("--overrides", default="{}")
    p.add_argument("--cache-dir", default="out/cache")
    a = p.parse_args()
    if a.kind in ("interior", "outdoor"):
        raise SystemExit("interior and outdoor are validation scenes: tune on gi_tuning_room")
    import json

    # without a Cycles reference of the kind, the seeds' mean stands in for it (it only scales the terms)
    found = list(Path(a.cache_dir).glob(f"cycles_reference_{a.kind}_*"))
    ref = reference(a.kind, LightPaths.of(4), Path(a.cache_dir)).astype(np.float64) if found else None
    scene = scene_of_kind(a.kind)
    mats = material_map(scene)
    for b in (int(x) for x in a.bounces.split(",")):
        s = still_settings(Settings(**LightPaths.of(b).overrides(), **json.loads(a.overrides)).validate(), scene)
        imgs = []
        for seed in range(a.seeds):
            r = Renderer(scene, replace(s, seed=300 + seed))
            imgs.append(r.render_still(0, a.samples).color[..., :3].astype(np.float64))
        mean = ref if ref is not None else np.mean(imgs, axis=0)
        var = np.var(np.stack(imgs), axis=0, ddof=1) / (mean * mean + 0.01)
        t = var.mean(axis=-1)
        order = np.sort(t.ravel())[::-1]
        per = "  ".join(f"{m.name} {t[mats == i].sum() / t.size:.1e}" for i, m in enumerate(scene.materials)
                        if (mats == i).any())
        top = order[: order.size // 1000].sum() / order.sum()
        print(f"max bounces {b}: variance relMSE {t.mean():.3e}  top0.1% {top:.2f}  load {os.getloadavg()[0]:.1f}",
              flush=True)
        print("    " + per, flush=True)


if __name__ == "__main__":
    main()
