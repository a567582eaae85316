"""Where permutation sampling loses on the many_lights flythrough (taa_variants' scene: 160x90, 24 frames, TAA,
references every 4th frame, 3 seeds): ReSTIR with and without `temporal_permutation`, the relMSE of each evaluated
frame, the same without each frame's 50 largest pixel terms (0.35 % of the pixels: the fireflies TAA holds), and
each frame's error split by pixel class (taa_own_error's edge mask, TAA's fresh pixels, the pixels whose
ReSTIR temporal pass found no history, the rest), with and without TAA: docs/measurements/temporal-stability.md,
"The flythrough with permutation sampling".

    python -m tools.experiments.flythrough_permutation --cache-dir /tmp/permute/refs [--define NAME]
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from restircl import Renderer, Settings, scenes
from restircl.eval.metrics import rel_mse_map
from restircl.eval.probe_defines import add_probe_defines
from restircl.eval.report.reference import get_reference

from .taa_own_error import edge_mask, restir_no_history

PARTS = ("edge+nohist", "edge", "nohist", "fresh", "rest")
TOP = 50  # the brightest errors: a frame's relMSE without its TOP largest pixel terms ("trimmed")


def split(m: np.ndarray, edge: np.ndarray, nohist: np.ndarray, fresh: np.ndarray) -> dict[str, float]:
    """The map's sum over each class's pixels, over all pixels (disjoint, in PARTS' order; fresh: TAA's n = 1)."""
    masks = {
        "edge+nohist": edge & nohist,
        "edge": edge & ~nohist,
        "nohist": ~edge & nohist,
        "fresh": ~edge & ~nohist & fresh,
    }
    masks["rest"] = ~(edge | nohist | fresh)
    return {k: float(m[v].sum() / m.size) for k, v in masks.items()}


def run(sc, refs: dict, every: list[int], seed: int, settings: dict) -> dict:
    r = Renderer(sc, Settings(method="restir", seed=seed, **settings))
    out = {}
    for f in range(sc.frames):
        fr = r.render_frame(f, aovs=False)
        if f in every:
            g = r.read_gbuffer()
            edge, nohist, fresh = edge_mask(g), restir_no_history(r), r.history_length() <= 1.0
            taa, raw = rel_mse_map(fr.color[..., :3], refs[f]), rel_mse_map(fr.noisy[..., :3], refs[f])
            out[f] = {
                "taa": float(taa.mean()),
                "taa_trim": float(np.sort(taa.ravel())[:-TOP].sum() / taa.size),
                "top_pixels": [int(i) for i in np.argsort(taa.ravel())[::-1][:TOP]],
                "sample": float(raw.mean()),
                "taa_parts": split(taa, edge, nohist, fresh),
                "sample_parts": split(raw, edge, nohist, fresh),
                "pixels": split(np.ones_like(taa), edge, nohist, fresh),
            }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cache-dir", default="out/refs")
    ap.add_argument("--define", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--seeds", type=int, default=3)
    a = ap.parse_args()
    if a.define:
        add_probe_defines(a.define)
    sc = scenes.many_lights(160, 90, frames=24)
    every = list(range(4, 24, 4))
    refs = {f: get_reference(sc, f, 15.0, cache_dir=a.cache_dir, log=lambda s: None).image[..., :3] for f in every}
    print(f"load {os.getloadavg()[0]:.1f}")
    for name, kw in (("no permutation", {"temporal_permutation": False}), ("permutation", {})):
        runs = [run(sc, refs, every, s, kw) for s in range(a.seeds)]
        per_seed = [np.mean([x[f]["taa"] for f in every]) for x in runs]
        print(f"{name}: relMSE per seed " + " ".join(f"{e:.4f}" for e in per_seed) + f"  mean {np.mean(per_seed):.4f}")
        trim = [np.mean([x[f]["taa_trim"] for f in every]) for x in runs]
        print(
            f"  without each frame's {TOP} largest pixel terms: "
            + " ".join(f"{e:.4f}" for e in trim)
            + f"  mean {np.mean(trim):.4f}"
        )
        for f in every:
            taa = [x[f]["taa"] for x in runs]
            print(
                f"  frame {f:2d} per seed "
                + " ".join(f"{e:.4f}" for e in taa)
                + "  sample "
                + " ".join(f"{x[f]['sample']:.3f}" for x in runs)
            )
        for key in ("taa_parts", "sample_parts", "pixels"):
            mean = {p: float(np.mean([x[f][key][p] for x in runs for f in every])) for p in PARTS}
            print(f"  {key:<12} " + "  ".join(f"{p} {v:.4f}" for p, v in mean.items()))
    print(f"load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
