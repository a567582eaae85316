"""Where the bounced light's variance per sample comes from (docs/measurements/error-vs-time.md, "Global illumination
against Cycles"): F12's still path (`auto`) with bounces at a fixed number of samples, against the cached Cycles
reference of the kind (`restircl compare` made it, with the same Light Paths), for variants given as Settings
overrides and compile-time defines of the kernels. Per variant: relMSE (mean and spread over seeds), seconds per
sample, the share of the relMSE in the worst 0.1 % of pixels (fireflies), and the same at Max Bounces 0 (the direct
light's own error, which the indirect error adds to). Only for tuning scenes: never run it on a validation kind.

    python -m tools.experiments.gi_variance --kind gi_tuning_room --samples 64 --seeds 3 \\
        --variant base= --variant tree='{"light_proposal": "tree"}' --variant nomis=-DSOME_DEFINE
"""

from __future__ import annotations

import argparse
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.metrics import rel_mse, rel_mse_map
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render import pipeline
from restircl.render.still_method import still_settings

from .gi_agreement import material_map


def reference(kind: str, paths: LightPaths, cache: Path) -> np.ndarray:
    """The cached Cycles reference of `kind` with these Light Paths (the one with the most samples)."""
    found = sorted(cache.glob(f"cycles_reference_{kind}_*{paths.tag}_*.npy"),
                   key=lambda p: int(p.name.split("_2x")[1].split("_")[0]))
    if not found:
        raise SystemExit(f"no Cycles reference of {kind} with {paths.describe()} in {cache}: run restircl compare")
    return np.load(found[-1])


def parse_variant(text: str) -> tuple[str, dict, tuple[str, ...]]:
    """name=JSON overrides and/or -D defines separated by spaces: 'tree={"light_proposal": "tree"} -DX=1'."""
    name, _, rest = text.partition("=")
    defines = tuple(w for w in rest.split() if w.startswith("-D"))
    body = " ".join(w for w in rest.split() if not w.startswith("-D"))
    return name, (json.loads(body) if body else {}), defines


def run_variant(kind: str, paths: LightPaths, overrides: dict, defines: tuple[str, ...], samples: int, seeds: int,
                ref: np.ndarray) -> dict:
    scene = scene_of_kind(kind)
    build = pipeline.build_program
    pipeline.build_program = lambda device, flags=None, **kw: build(  # type: ignore[assignment]
        device, flags, extra_options=(*kw.pop("extra_options", ()), *defines), **kw)
    try:
        s = still_settings(Settings(**{**paths.overrides(), **overrides}).validate(), scene)
        r = Renderer(scene, s)
        r.render_still(0, 2)
        errs, secs, tops, maps = [], [], [], []
        for seed in range(seeds):
            r = Renderer(scene, replace(s, seed=100 + seed))
            t0 = time.perf_counter()
            img = r.render_still(0, samples).color[..., :3]
            secs.append((time.perf_counter() - t0) / samples)
            errs.append(rel_mse(img, ref))
            maps.append(rel_mse_map(img, ref))
            t = np.sort(maps[-1].ravel())[::-1]
            tops.append(float(t[: max(t.size // 1000, 1)].sum() / t.sum()))
        mats = material_map(scene)
    finally:
        pipeline.build_program = build  # type: ignore[assignment]
    mean_map = np.mean(maps, axis=0)
    per_material = {m.name: float(mean_map[mats == i].sum() / mean_map.size) for i, m in enumerate(scene.materials)
                    if (mats == i).any()}
    return {"per_material_rel_mse": per_material, "overrides": overrides, "defines": defines,
            "samples": samples, "rel_mse": float(np.mean(errs)),
            "rel_mse_each": errs, "seconds_per_sample": float(np.median(secs)), "top_0.1%_share": float(np.mean(tops)),
            "method": s.method}


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--kind", default="gi_tuning_room")
    p.add_argument("--max-bounces", type=int, default=4)
    p.add_argument("--samples", type=int, default=64)
    p.add_argument("--seeds", type=int, default=3)
    p.add_argument("--variant", action="append", default=[])
    p.add_argument("--cache-dir", default="out/cache")
    p.add_argument("--out", default="out/gi_variance.jsonl")
    a = p.parse_args()
    if a.kind in ("interior", "outdoor"):
        raise SystemExit("interior and outdoor are validation scenes: tune on gi_tuning_room")
    paths = LightPaths.of(a.max_bounces)
    ref = reference(a.kind, paths, Path(a.cache_dir))
    for text in a.variant or ["base="]:
        name, overrides, defines = parse_variant(text)
        load = os.getloadavg()[0]
        res = {"variant": name, "kind": a.kind, "light_paths": paths.describe(), "load": load,
               **run_variant(a.kind, paths, overrides, defines, a.samples, a.seeds, ref)}
        print(f"{name:<14} relMSE {res['rel_mse']:.3e} ({', '.join(f'{e:.2e}' for e in res['rel_mse_each'])}) "
              f"{res['seconds_per_sample'] * 1e3:6.1f} ms/spp  x time {res['rel_mse'] * res['seconds_per_sample']:.3e}"
              f"  top0.1% {res['top_0.1%_share']:.2f}  load {load:.1f}", flush=True)
        print("    " + "  ".join(f"{k} {v:.1e}" for k, v in res["per_material_rel_mse"].items()), flush=True)
        with open(a.out, "a") as f:
            f.write(json.dumps(res) + "\n")


if __name__ == "__main__":
    main()
