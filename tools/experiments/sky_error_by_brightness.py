"""Where F12's error on the tuning sky lies, against Cycles' at the same sample count
(docs/measurements/error-vs-time.md, "A world alone: one candidate"): per-pixel squared relative error of the
luminance against the cached 2 x 1024-spp Cycles reference, averaged over two seeds each, grouped by deciles of the
reference's brightness (the darkest deciles are the shadows, lit by the sky alone). Needs bpy and the reference
(`restircl compare --kinds sky`).

    python -m tools.experiments.sky_error_by_brightness [--samples 64]
"""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np
from restircl import Renderer
from restircl.eval.cycles import bridge as cycles
from restircl.eval.cycles.compare import REFERENCE_SPP, cycles_reference, ours_settings
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH, held_out

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=64)
    a = ap.parse_args()
    scene = held_out("sky", WIDTH, HEIGHT)
    sc = cycles.to_bpy(scene)
    ref = cycles_reference("sky", scene, sc, REFERENCE_SPP, 2, None, print).image
    lum_ref = ref @ LUMINANCE
    theirs = [cycles.render(sc, samples=a.samples, seed=seed, threads=2).image for seed in (1, 2)]
    ours = [Renderer(scene, replace(ours_settings("auto", scene), seed=seed)).render_still(0, a.samples).color[..., :3]
            for seed in (7, 8)]

    def err(images: list[np.ndarray]) -> np.ndarray:
        return np.mean([(im @ LUMINANCE - lum_ref) ** 2 / (lum_ref ** 2 + 1e-2) for im in images], axis=0)

    eo, ec = err(ours), err(theirs)
    print(f"{a.samples} samples: relMSE ours {[f'{rel_mse(o, ref):.3e}' for o in ours]}, "
          f"Cycles {[f'{rel_mse(c, ref):.3e}' for c in theirs]}")
    edges = np.quantile(lum_ref, np.linspace(0.0, 1.0, 11))
    for k in range(10):
        m = (lum_ref >= edges[k]) & (lum_ref <= edges[k + 1])
        print(f"decile {k}: luminance {edges[k]:.3g}..{edges[k + 1]:.3g}: ours {eo[m].sum() / eo.sum():5.1%} of our "
              f"error, Cycles {ec[m].sum() / ec.sum():5.1%} of theirs; ours / Cycles there "
              f"{eo[m].mean() / max(float(ec[m].mean()), 1e-30):5.2f}")


if __name__ == "__main__":
    main()
