"""Ours against Cycles at equal samples on a kind with bounces, and where the error's heavy tail lies
(docs/measurements/error-vs-time.md, "Outdoor with 4 bounces: where the 2.33 % and the 1-s loss come from"): F12's
still settings (`auto`) at N frames and Cycles at N spp, each over independent seeds, against the kind's Cycles
reference of the same Light Paths. Per side: the relMSE's median and mean over the seeds (the mean is what 1/N
scaling holds for; with a heavy tail the median of few repetitions falls far below it), and per material of the
first surface the samples above k x (reference + 0.1), their count and their share of the relMSE. With --mutual,
our seeds are split into two independent halves whose mean images are compared with each other and with Cycles,
pixel by pixel and over 8 x 8 blocks, with each material's image-sum ratio and its standard error over the seeds:
what our own noise alone gives beside the distance to Cycles.

    python -m tools.experiments.equal_sample_tails --kind outdoor --reference REF.npy --max-bounces 4 \\
        --samples 1 --seeds 100 --cycles
    python -m tools.experiments.equal_sample_tails --kind outdoor --reference REF.npy --samples 64 --seeds 12 \\
        --mutual
    ... --material chrome.metallic=0 --material chrome.roughness=0.5   (a diagnosis of ours only: no Cycles)
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from restircl import Renderer, Settings
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.paths import LightPaths
from restircl.eval.metrics import rel_mse, rel_mse_map
from restircl.eval.scenes.kinds import scene_of_kind
from restircl.render.still_method import still_settings

from .gi_agreement import blocks, material_map

THRESHOLDS = (10.0, 30.0, 100.0)


def ours(scene, paths: LightPaths, frames: int, seeds: list[int]) -> tuple[np.ndarray, float]:
    """(S, H, W, 3) images of F12's still settings at `frames` frames, one per seed, and CPU ms per frame."""
    base = still_settings(Settings(**paths.overrides()).validate(), scene)
    Renderer(scene, base).render_still(0, 1)  # the kernels' build, outside the timed frames
    imgs, cpu = [], 0.0
    for seed in seeds:
        base.seed = seed
        r = Renderer(scene, base)
        c0 = time.process_time()
        imgs.append(r.render_still(0, frames).color[..., :3].astype(np.float64))
        cpu += time.process_time() - c0
    return np.stack(imgs), cpu * 1e3 / (frames * len(seeds))


def theirs(scene, paths: LightPaths, spp: int, seeds: list[int]) -> tuple[np.ndarray, float]:
    """(S, H, W, 3) Cycles images at `spp` samples, one per seed, and render ms per sample (2 threads)."""
    sc = cycles.to_bpy(scene)
    imgs, secs = [], 0.0
    for seed in seeds:
        res = cycles.render(sc, samples=spp, seed=seed, threads=2, paths=paths.cycles())
        imgs.append(res.image[..., :3].astype(np.float64))
        secs += res.render_seconds
    return np.stack(imgs), secs * 1e3 / (spp * len(seeds))


def tail_counts(imgs: np.ndarray, ref: np.ndarray, mats: np.ndarray, materials: int) -> dict:
    """Per seed its relMSE ("per_seed"), and per material index (-1: no surface) the number of samples above
    k x (ref + 0.1) for k in THRESHOLDS ("counts") and the material's share of the relMSE summed over the seeds."""
    maps = np.stack([rel_mse_map(x, ref) for x in imgs])
    ratio = imgs.mean(-1) / (ref.mean(-1)[None] + 0.1)
    out: dict = {"per_seed": maps.mean(axis=(1, 2)), "counts": {}, "share": {}}
    for i in [*range(materials), -1]:
        sel = np.broadcast_to(mats == i, ratio.shape)
        if sel.any():
            out["counts"][i] = [int(((ratio > k) & sel).sum()) for k in THRESHOLDS]
            out["share"][i] = float(maps[sel].sum() / maps.sum()) if maps.sum() > 0 else 0.0
    return out


def tails(label: str, imgs: np.ndarray, ref: np.ndarray, mats: np.ndarray, names: list[str]) -> None:
    """relMSE over the seeds, and per material the samples above k x (ref + 0.1) and the relMSE's share there."""
    t = tail_counts(imgs, ref, mats, len(names))
    per = t["per_seed"]
    print(
        f"{label}: relMSE median {np.median(per):.4g} mean {per.mean():.4g} (seeds {len(per)}; "
        f"without the top 5 %: {np.sort(per)[: max(1, int(len(per) * 0.95))].mean():.4g})"
    )
    for i, counts in t["counts"].items():
        name = names[i] if i >= 0 else "(no surface)"
        text = " ".join(f">{k:g}x {c}" for k, c in zip(THRESHOLDS, counts, strict=True))
        print(f"    {name:14s} {text}  share of the relMSE {t['share'][i]:.3f}")


def mutual(imgs: np.ndarray, ref: np.ndarray, mats: np.ndarray, names: list[str]) -> None:
    """Two independent halves of our seeds against each other and against Cycles; per material the sum ratio of all
    our seeds' mean to Cycles' with its standard error over the seeds."""
    h = len(imgs) // 2
    a, b = imgs[:h].mean(0), imgs[h : 2 * h].mean(0)
    print(
        f"halves of {h} seeds: mutual relMSE {rel_mse(a, b):.3e}, each against Cycles {rel_mse(a, ref):.3e} / "
        f"{rel_mse(b, ref):.3e}; 8 x 8 blocks mutual {rel_mse(blocks(a, 8), blocks(b, 8)):.2e}, against Cycles "
        f"{rel_mse(blocks(a, 8), blocks(ref, 8)):.2e} / {rel_mse(blocks(b, 8), blocks(ref, 8)):.2e}"
    )
    m = imgs.mean(0)
    print(
        f"all {len(imgs)} seeds: relMSE {rel_mse(m, ref):.3e}, 8 x 8 blocks "
        f"{rel_mse(blocks(m, 8), blocks(ref, 8)):.2e}, sum ratio {m.sum() / ref.sum():.4f}"
    )
    for i, name in enumerate(names):
        sel = mats == i
        if not sel.any():
            continue
        per = np.array([x[sel].sum() for x in imgs]) / ref[sel].sum()
        print(
            f"    {name:14s} {int(sel.sum()):6d} px  sum ratio {m[sel].sum() / ref[sel].sum():.4f} "
            f"+- {per.std(ddof=1) / np.sqrt(len(per)):.4f}"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", default="outdoor")
    ap.add_argument("--reference", required=True, help="the Cycles reference (.npy) of the kind, same Light Paths")
    ap.add_argument("--max-bounces", type=int, default=4)
    ap.add_argument("--samples", type=int, default=1, help="frames of ours and spp of Cycles")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=2000)
    ap.add_argument("--cycles", action="store_true", help="also Cycles at the same samples (seeds first-seed + ...)")
    ap.add_argument("--mutual", action="store_true", help="our seeds in two halves against each other")
    ap.add_argument("--material", action="append", default=[], help="name.attribute=value on our scene only")
    a = ap.parse_args()
    ref = np.load(a.reference)[..., :3].astype(np.float64)
    h, w = ref.shape[:2]
    scene = scene_of_kind(a.kind, w, h)
    mats = material_map(scene)  # of the scene as built, before any override
    for text in a.material:
        key, value = text.split("=")
        name, attr = key.split(".")
        for m in scene.materials:
            if m.name == name:
                setattr(m, attr, float(value))
    names = [m.name for m in scene.materials]
    paths = LightPaths.of(a.max_bounces)
    seeds = list(range(a.first_seed, a.first_seed + a.seeds))
    imgs, ms = ours(scene, paths, a.samples, seeds)
    tails(f"ours {a.samples} frames ({ms:.1f} CPU ms per frame)", imgs, ref, mats, names)
    if a.mutual:
        mutual(imgs, ref, mats, names)
    if a.cycles and not a.material:
        cyc, cms = theirs(scene, paths, a.samples, seeds)
        tails(f"Cycles {a.samples} spp ({cms:.1f} render ms per sample)", cyc, ref, mats, names)
    print(f"load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
