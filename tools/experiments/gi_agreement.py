"""Where a converged render of ours with bounces differs from Cycles' (docs/measurements/error-vs-time.md, "Global
illumination against Cycles"): for each scene kind, the cached references of `restircl compare` (Cycles' 2 x spp and
our converged image, both with the same Light Paths; made here if missing), their relMSE beside each side's own
estimated relMSE (what noise alone would give), the share of the relMSE in the worst pixels, the relMSE of 8 x 8
block means (noise shrinks ~64x there, a difference does not), and per material of the pixel's first surface its
share of the relMSE and the ratio of the image sums there. Writes both images and the per-pixel relMSE as PNGs.

    python -m tools.experiments.gi_agreement --kinds interior,outdoor --max-bounces 4 --spp 1024 \\
        --ours-seconds 600 --cache-dir out/cache --out out/gi
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.compare import cycles_reference
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.metrics import rel_mse, rel_mse_map
from restircl.eval.report.reference import get_reference
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.io.images import to_srgb8


def material_map(scene, device=None) -> np.ndarray:
    """(H, W) index of the material of each pixel's first surface (-1: none), from one unjittered frame's G-buffer:
    an emitter by its emission, a metal by its zero diffuse albedo, any other by the chromaticity of its diffuse
    albedo (a specular layer scales the G-buffer's albedo by a grey factor, which the chromaticity ignores)."""
    r = Renderer(scene, Settings(method="ris", jitter=False), device)
    r.render_still(0, 1)
    g = r.read_gbuffer()
    alb, emi = g["albedo"][..., :3].astype(np.float64), g["emission"][..., :3].astype(np.float64)

    def chroma(c: np.ndarray) -> np.ndarray:
        return c / np.maximum(c.sum(axis=-1, keepdims=True), 1e-12)

    mats = scene.materials
    emitting = np.array([m.is_emissive for m in mats])
    metal = np.array([not m.is_emissive and float(m.metallic) == 1.0 for m in mats])
    table = np.array([chroma(np.asarray(m.albedo, np.float64)) for m in mats])
    dist = np.abs(chroma(alb)[:, :, None, :] - table[None, None]).sum(axis=-1)
    dist[..., emitting | metal] = np.inf
    out = dist.argmin(axis=-1)
    rad = np.array([m.radiance for m in mats])
    by_emission = np.abs(emi[:, :, None, :] - rad[None, None]).sum(axis=-1)
    by_emission[..., ~emitting] = np.inf
    out = np.where(emi.sum(axis=-1) > 0, by_emission.argmin(axis=-1), out)
    if metal.any():
        out = np.where((emi.sum(axis=-1) == 0) & (alb.sum(axis=-1) == 0), int(np.flatnonzero(metal)[0]), out)
    return np.where(np.abs(g["normal"][..., :3]).sum(axis=-1) > 0, out, -1)


def blocks(img: np.ndarray, k: int) -> np.ndarray:
    h, w = (img.shape[0] // k) * k, (img.shape[1] // k) * k
    return img[:h, :w, :3].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))


def analyse(kind: str, paths: LightPaths, spp: int, seconds: float, cache: Path, out: Path, device=None) -> dict:
    scene = scene_of_kind(kind)
    ref = cycles_reference(kind, scene, cycles.to_bpy(scene), spp, 2, cache, print, paths)
    ours = get_reference(scene, 0, seconds, device=device, cache_dir=cache, overrides=paths.overrides())
    t = rel_mse_map(ours.image, ref.image)
    order = np.sort(t.ravel())[::-1]
    n = order.size
    mats = material_map(scene, device)
    per_material = {}
    for i, m in enumerate(scene.materials):
        sel = mats == i
        if sel.sum() == 0:
            continue
        per_material[m.name] = {"pixels": int(sel.sum()), "share_of_rel_mse": float(t[sel].sum() / t.sum()),
                                "rel_mse_there": float(t[sel].mean()),
                                "sum_ratio": float(ours.image[sel].sum() / max(ref.image[sel].sum(), 1e-30))}
    result = {
        "kind": kind, "light_paths": paths.describe(), "rel_mse": rel_mse(ours.image, ref.image),
        "sum_ratio": float(ours.image.sum() / ref.image.sum()),
        "cycles": {"spp": ref.spp, "seconds": ref.seconds, "est_rel_mse": ref.est_rel_mse,
                   "sum_rel_std": ref.sum_rel_std},
        "ours": {"method": ours.method, "frames": ours.frames, "seconds": ours.seconds,
                 "est_rel_mse": ours.est_rel_mse},
        "share_top_0.1%": float(order[: max(n // 1000, 1)].sum() / order.sum()),
        "share_top_1%": float(order[: n // 100].sum() / order.sum()),
        "rel_mse_without_top_1%": float(order[n // 100:].mean()),
        "rel_mse_blocks_8": rel_mse(blocks(ours.image, 8), blocks(ref.image, 8)),
        "per_material": per_material,
    }
    out.mkdir(parents=True, exist_ok=True)
    from PIL import Image

    tag = f"{kind}{paths.tag}"
    Image.fromarray(to_srgb8(ours.image)).save(out / f"gi_{tag}_ours.png")
    Image.fromarray(to_srgb8(ref.image)).save(out / f"gi_{tag}_cycles.png")
    heat = np.clip(np.sqrt(t / max(float(np.quantile(t, 0.999)), 1e-12)), 0, 1)
    Image.fromarray((np.stack([heat, heat, heat], -1) * 255).astype(np.uint8)).save(out / f"gi_{tag}_relmse.png")
    return result


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--kinds", default="interior,outdoor")
    p.add_argument("--max-bounces", type=int, default=4)
    p.add_argument("--diffuse-bounces", type=int, default=None)
    p.add_argument("--glossy-bounces", type=int, default=None)
    p.add_argument("--spp", type=int, default=1024)
    p.add_argument("--ours-seconds", type=float, default=600.0)
    p.add_argument("--cache-dir", default="out/cache")
    p.add_argument("--out", default="out/gi")
    a = p.parse_args()
    paths = LightPaths.of(a.max_bounces, a.diffuse_bounces, a.glossy_bounces)
    load = os.getloadavg()
    results = [analyse(k, paths, a.spp, a.ours_seconds, Path(a.cache_dir), Path(a.out)) for k in a.kinds.split(",")]
    record = {"load_before": load, "load_after": os.getloadavg(), "results": results}
    path = Path(a.out) / f"gi_agreement{paths.tag}_{a.spp}.json"
    path.write_text(json.dumps(record, indent=1))
    print(json.dumps(record, indent=1))


if __name__ == "__main__":
    main()
