"""Ghosting through glass under TAA (issue 39): the camera of eval/scenes/glass_orbit.py orbits a glass sphere
(smooth, or --roughness); each variant renders the animation (ReSTIR DI + the bounced light: the path pass at the
sphere's pixels, ReSTIR GI at the rest; one sample per pixel per frame) with several
seeds, scored against per-frame converged stills over the frames after FIRST. Two figures per variant, on the whole
image and on the sphere's pixels: the mean relMSE of one run (what a viewer sees: noise and ghost) and the relMSE of
the mean over the seeds (the noise shrinks by the seed count, the ghost, a lag behind the view, stays).

    python tools/experiments/taa_glass_ghost.py --seeds 8
    python tools/experiments/taa_glass_ghost.py --seeds 4 --ref-spp 512 --roughness 0.3 \
        --only "default,no history,no TAA"
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.glass_orbit import glass_orbit
from restircl.render import pipeline
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings

FIRST = 4
BOUNCES = 4  # camera -> glass -> glass -> wall: the wall's light reaches the eye after two refractions
VARIANTS = {"TAA, glass keeps its history": (True, ("-DGLASS_KEEPS_HISTORY",)),
            "TAA, glass rated as a mirror: no history (default)": (True, ()),
            "TAA, glass as a mirror, raise towards 0.5": (True, ("-DTAA_GLOSSY_ALPHA=0.5f",)),
            "TAA, glass as a mirror, no raise, clip box a quarter": (True, ("-DTAA_GLOSSY_ALPHA=0.1f",)),
            "TAA, glass as a mirror, no raise, clip box a half": (True, ("-DTAA_GLOSSY_ALPHA=0.1f",
                                                                        "-DTAA_GLOSSY_GAMMA=0.5f")),
            "no TAA": (False, ())}


def paths(**kw) -> Settings:
    return Settings(max_bounces=BOUNCES, diffuse_bounces=BOUNCES, glossy_bounces=BOUNCES,
                    transmission_bounces=BOUNCES, **kw)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--frames", type=int, default=12)
    ap.add_argument("--deg", type=float, default=3.0)
    ap.add_argument("--ref-spp", type=int, default=1024)
    ap.add_argument("--only", default="", help="comma-separated words: run the variants whose name holds one")
    ap.add_argument("--ref-cache", default="", help="an .npy file holding the references (made if absent)")
    ap.add_argument("--roughness", type=float, default=0.0, help="the sphere's roughness (0: smooth glass)")
    a = ap.parse_args()
    scene = glass_orbit(frames=a.frames, deg_per_frame=a.deg, roughness=a.roughness)
    t0 = time.time()
    if a.ref_cache and os.path.exists(a.ref_cache):
        refs = list(np.load(a.ref_cache))
    else:
        ref_r = Renderer(scene, paths(method="ris", candidates=16, taa=False, seed=5))
        refs = [ref_r.render_still(f, a.ref_spp).color[..., :3].astype(np.float64) for f in range(a.frames)]
        if a.ref_cache:
            np.save(a.ref_cache, np.stack(refs))
    bare = Renderer(glass_orbit(frames=a.frames, deg_per_frame=a.deg, glass=False), paths(taa=False))
    full = Renderer(scene, paths(taa=False))
    mask = [bare.render_frame(f).depth != full.render_frame(f).depth for f in range(a.frames)]
    print("| variant | relMSE, one run | median over seeds | on the sphere | of the seeds' mean | on the sphere |")
    print(f"references {a.ref_spp} spp: {time.time() - t0:.0f} s; sphere pixels {np.mean(mask[FIRST:]):.0%}")
    build = pipeline.build_program
    for name, (taa, opts) in VARIANTS.items():
        if a.only and not any(w in name for w in a.only.split(",")):
            continue
        try:
            pipeline.build_program = lambda dev, flags, _o=opts, **kw: build(dev, flags, extra_options=_o)
            runs = []
            for s in range(a.seeds):
                r = Renderer(scene, paths(seed=100 + s, taa=taa))
                runs.append([r.render_frame(f, aovs=False).color[..., :3].astype(np.float64)
                             for f in range(a.frames)])
        finally:
            pipeline.build_program = build
        frames = range(FIRST, a.frames)
        one = np.mean([[rel_mse(run[f], refs[f]) for f in frames] for run in runs])
        one_g = np.mean([[rel_mse(run[f][mask[f]], refs[f][mask[f]]) for f in frames] for run in runs])
        med = np.median([np.mean([rel_mse(run[f], refs[f]) for f in frames]) for run in runs])
        mean_img = [np.mean([run[f] for run in runs], axis=0) for f in range(a.frames)]
        ghost = np.mean([rel_mse(mean_img[f], refs[f]) for f in frames])
        ghost_g = np.mean([rel_mse(mean_img[f][mask[f]], refs[f][mask[f]]) for f in frames])
        print(f"| {name} | {one:.4g} | {med:.4g} | {one_g:.4g} | {ghost:.4g} | {ghost_g:.4g} |", flush=True)


if __name__ == "__main__":
    main()
