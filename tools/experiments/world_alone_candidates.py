"""A world that is the only light, rendered as F12 renders it (`still_settings`, Sobol sampler), with 1, 2 or 4
light candidates from the alias or the cumulative table: relMSE at 64 and 256 frames and CPU ms per frame
(docs/measurements/error-vs-time.md, "A world alone: one candidate"). Also how the error splits over the image: the
share of it in the darkest 30 % of the reference's pixels (the shadows, where RIS's unshadowed target sends the one
shadow ray towards an occluded sun).

    python -m tools.experiments.world_alone_candidates --world sunny|grey \
        [--variants alias:4,alias:1,alias:2,cdf:1] [--rounds 2] [--seeds 7,8]

`--world sunny`: the tuning sky, against the cached Cycles reference; `--world grey`: the same sky without its
sun, against our own RIS reference (4096 random frames, 4 candidates).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np
from restircl import Environment, Renderer, Settings, still_settings
from restircl.eval.metrics import rel_mse
from restircl.eval.scenes.held_out import HEIGHT, WIDTH, held_out
from restircl.render import qmc
from restircl.scenes.hdri_sky import sky_map

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def reference(scene, world: str) -> np.ndarray:
    if world == "sunny":
        from restircl.eval.cycles import bridge as cycles
        from restircl.eval.cycles.compare import REFERENCE_SPP, cycles_reference
        return cycles_reference("sky", scene, cycles.to_bpy(scene), REFERENCE_SPP, 2, None, print).image
    r = Renderer(scene, Settings(method="ris", candidates=4, sampler="random", seed=99))
    return r.render_still(0, 4096).color[..., :3]


def renderer_with_table(scene, settings: Settings, table: str) -> Renderer:
    """A renderer whose world table is `table`, whatever qmc.environment_table would choose."""
    chosen = qmc.environment_table
    qmc.environment_table = lambda s: table  # type: ignore[assignment]
    try:
        r = Renderer(scene, settings)
    finally:
        qmc.environment_table = chosen  # type: ignore[assignment]
    got = r.device_scene.lights.environment
    assert got is not None and got.kind == table
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--world", choices=("sunny", "grey"), default="sunny")
    ap.add_argument("--variants", default="alias:4,alias:1,alias:2,cdf:1", help="table:candidates, ...")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--seeds", default="7,8")
    a = ap.parse_args()
    scene = held_out("sky", WIDTH, HEIGHT)
    if a.world == "grey":
        sun = np.array([-0.55, 0.45, 0.45])
        scene.environment = Environment("grey_sky", color=(1.0, 1.0, 1.0), strength=1.0,
                                        image=sky_map(256, 512, sun_scale=0.0, sun=sun))
    ref = reference(scene, a.world)
    lum_ref = ref @ LUMINANCE
    dark = lum_ref < np.quantile(lum_ref, 0.3)
    for rnd in range(a.rounds):
        for variant in a.variants.split(","):
            table, cand = variant.split(":")
            for seed in (int(s) for s in a.seeds.split(",")):
                s = still_settings(replace(Settings(candidates=int(cand)), seed=seed), scene)
                r = renderer_with_table(scene, s, table)
                r.render_still(0, 2)  # warm-up: program build, upload
                for n in (64, 256):
                    c0 = time.process_time()
                    img = r.render_still(0, n).color[..., :3]
                    cpu = time.process_time() - c0
                    e = (img @ LUMINANCE - lum_ref) ** 2 / (lum_ref ** 2 + 1e-2)
                    print(f"round {rnd} {table:5} {s.candidates} cand (BSDF MIS sample {s.bsdf_mis_sample}) "
                          f"seed {seed} n {n:4}: relMSE {rel_mse(img, ref):.3e}, "
                          f"darkest 30 % hold {e[dark].sum() / e.sum():.2f}, {cpu * 1e3 / n:6.2f} CPU ms/frame",
                          flush=True)


if __name__ == "__main__":
    main()
