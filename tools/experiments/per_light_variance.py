"""Issue 23, lever 1: where the tuning studio's per-sample error comes from. Renders the scene with all its lights
and with each light alone, with Cycles (direct light only) and with F12's still path (`still_settings`: the per-pixel
light pick, and with --array the light array's), two independent renders of N samples each, and prints the relMSE
of one N-sample image estimated from the pair: mean((a - b)^2 / 2 / (r^2 + 0.01)), r the mean of every render of
that light set (a denominator only), and the same variance over the all-lights image's r^2 (its share of the full
scene's error). No reference needed; both renderers' estimators are unbiased.

    python -m tools.experiments.per_light_variance [--samples 64] [--lights all,square,...] [--no-cycles]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np
from restircl import Renderer, Settings, still_settings
from restircl.eval.cycles import bridge as cycles
from restircl.eval.scenes.held_out import studio


def pair_rel_mse(a: np.ndarray, b: np.ndarray, ref: np.ndarray) -> float:
    d2 = (np.asarray(a, np.float64) - b) ** 2 / 2
    return float(np.mean(d2 / (ref * ref + 0.01)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--lights", default=None, help="comma-separated: all and/or light names (default: every set)")
    ap.add_argument("--no-cycles", action="store_true")
    a = ap.parse_args()
    full = studio()
    sets = [("all", list(full.lights))] + [(light.name, [light]) for light in full.lights]
    wanted = a.lights.split(",") if a.lights else [name for name, _ in sets]
    full_ref = None
    for name, lights in sets:
        if name != "all" and name not in wanted:  # the all-lights set always renders: its r^2 is the shares' scale
            continue
        scene = replace(full, lights=lights)
        images: dict[str, list[np.ndarray]] = {}
        if not a.no_cycles:
            bs = cycles.to_bpy(scene)
            cycles.render(bs, samples=1, threads=2)
            images["cycles"] = [cycles.render(bs, samples=a.samples, seed=s, threads=2).image[..., :3] for s in (1, 2)]
        for tag, proposal in (("ours", "auto"), ("array", "array")):
            st = still_settings(Settings(light_proposal=proposal), scene)
            images[tag] = [Renderer(scene, replace(st, seed=s)).render_still(0, a.samples).color[..., :3]
                           for s in (1, 2)]
        ref = np.mean([x for v in images.values() for x in v], axis=0).astype(np.float64)
        if name == "all":
            full_ref = ref
            if name not in wanted:
                continue
        assert full_ref is not None
        own = "  ".join(f"{k} {pair_rel_mse(*v, ref):.2e}" for k, v in images.items())
        share = "  ".join(f"{k} {pair_rel_mse(*v, full_ref):.2e}" for k, v in images.items())
        print(f"{name:<10} relMSE at {a.samples} spp: {own}  | over the all-lights r^2: {share}", flush=True)


if __name__ == "__main__":
    main()
