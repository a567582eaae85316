"""ReSTIR GI on scenes with glass (issue 39). ReSTIR GI's initial sample is one BSDF sample from the visible point
x0 reconnected at the secondary vertex as a reflection: a sample that refracts at x0 leaves an empty reservoir, so
at a glass pixel it can only estimate the reflected part of the bounced light. Three ways for animation frames of a
scene that refracts (render/plan.py path_plan): the path pass alone (gi_reuse off; what such scenes ran before),
ReSTIR GI everywhere (forced: the plan told the scene does not refract), and the split (the default now): the path
pass at the pixels whose first surface transmits, ReSTIR GI at the rest. This renders animation frames of a static
camera (ReSTIR DI and one of those, 8 bounces of every kind, one sample per pixel per frame) and scores the frame's
own sample (the Noisy Direct pass: direct and bounced light, before TAA) and TAA's output against a converged still,
on the glass pixels (where the first surface transmits: Transmission Color > 0) and on the rest: the mean relMSE of
one frame after FIRST, the relMSE of the mean of those frames (the noise shrinks, a bias stays) and the ratio of the
mean brightness to the reference's.

    python tools/experiments/restir_gi_glass.py --frames 24 --ref-spp 512
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np
from restircl.eval.scenes.glass import glass_table
from restircl.eval.scenes.glass_pane import glass_pane
from restircl.render import plan
from restircl.render.pipeline import Renderer
from restircl.settings.table import Settings

FIRST = 8
B = 8


def paths(**kw) -> Settings:
    return Settings(max_bounces=B, diffuse_bounces=B, glossy_bounces=B, transmission_bounces=B, **kw)


def score(frames: list[np.ndarray], ref: np.ndarray, mask: np.ndarray) -> tuple[float, float, float]:
    """(mean relMSE of one frame, relMSE of the frames' mean, mean brightness / the reference's) on mask's pixels"""
    den = ref**2 + 0.01
    one = float(np.mean([((f - ref) ** 2 / den)[mask].mean() for f in frames]))
    mean = np.mean(frames, axis=0)
    return one, float(((mean - ref) ** 2 / den)[mask].mean()), float(mean[mask].mean() / ref[mask].mean())


VARIANTS = {"path pass alone": "paths", "ReSTIR GI everywhere": "gi", "split (default)": "split"}


def run(scene, frames: int, variant: str) -> tuple[list[np.ndarray], np.ndarray, float]:
    """The frames' own samples after FIRST, TAA's last output and the mean frame time (ms)."""
    real = plan.path_plan
    if variant == "gi":
        plan.path_plan = lambda s, x, h: real(s, dataclasses.replace(x, transmission=False), h)
    try:
        r = Renderer(scene, paths(method="restir", seed=3, gi_reuse=variant != "paths"))
        out, ms = [], []
        for k in range(frames):
            f = r.render_frame(0)
            if k >= FIRST:
                out.append(f.noisy[..., :3].astype(np.float64))
                ms.append(f.ms)
        p = r.last_plan
        assert p is not None and (p.gi, p.paths) == {"paths": (False, True), "gi": (True, False),
                                                     "split": (True, True)}[variant]
    finally:
        plan.path_plan = real
    return out, f.color[..., :3].astype(np.float64), float(np.mean(ms))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--ref-spp", type=int, default=512)
    ap.add_argument("--width", type=int, default=48)
    ap.add_argument("--height", type=int, default=36)
    a = ap.parse_args()
    for name, scene in (("glass_table", glass_table(a.width, a.height)), ("glass_pane", glass_pane(a.width, a.height))):
        t0 = time.perf_counter()
        still = Renderer(scene, paths(method="ris", light_passes=True)).render_still(0, samples=a.ref_spp)
        ref = still.color[..., :3].astype(np.float64)
        glass = np.repeat((still.transmission_color.max(axis=-1) > 0)[..., None], 3, axis=-1)
        print(f"{name}: reference {a.ref_spp} spp in {time.perf_counter() - t0:.0f} s; glass pixels "
              f"{glass[..., 0].mean():.1%}")
        for label, variant in VARIANTS.items():
            frames, taa, ms = run(scene, a.frames, variant)
            for part, mask in (("glass", glass), ("rest", ~glass)):
                one, mean, ratio = score(frames, ref, mask)
                taa_err = float(((taa - ref) ** 2 / (ref**2 + 0.01))[mask].mean())
                print(f"  {label:20s} {part:5s}: one frame {one:.3f}, mean of {len(frames)} {mean:.4f}, "
                      f"brightness x{ratio:.3f}, TAA {taa_err:.3f}; {ms:.0f} ms/frame")


if __name__ == "__main__":
    main()
