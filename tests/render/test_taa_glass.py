"""Smooth glass under a moving camera (docs/design.md, "Glass under motion"): the primary hit of a pixel seen through
glass is the glass surface, and its motion vector is that surface's motion. What the glass shows moves with the view
instead, so reprojected history shows it where it was (a ghost); but one path per frame through smooth glass is so
noisy that dropping the history there, as TAA does on a sharp mirror, costs more than the ghost (measured with
tools/experiments/taa_glass_ghost.py: relMSE 1.07 keeping it, 2.10 dropping it, 17.3 without TAA; on the
sphere's pixels 4.4 against 13.3). So
surface/view_dependence.h leaves dielectric lobes out; GLASS_VIEW_DEPENDENT rates them as mirrors (the negative
control)."""

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.eval.scenes.glass_orbit import glass_orbit

from ..bias_controls import built_with
from ..helpers import rel_mse

FRAMES, FIRST_SCORED, SEEDS = 12, 4, 8
BOUNCES = 4  # camera -> glass -> glass -> wall: the wall's light reaches the eye after two refractions


def paths(**kw) -> Settings:
    return Settings(max_bounces=BOUNCES, diffuse_bounces=BOUNCES, glossy_bounces=BOUNCES,
                    transmission_bounces=BOUNCES, **kw)


def sphere_pixels(device) -> list[np.ndarray]:
    """Per frame, the pixels where the camera sees the sphere: where the depth changes when it is left out."""
    full = Renderer(glass_orbit(frames=FRAMES), paths(taa=False), device)
    bare = Renderer(glass_orbit(frames=FRAMES, glass=False), paths(taa=False), device)
    return [full.render_frame(f).depth != bare.render_frame(f).depth for f in range(FRAMES)]


def taa_error(scene, refs: list[np.ndarray], mask: list[np.ndarray], seed: int, device) -> float:
    """Mean relMSE on the sphere's pixels of the TAA output against each frame's reference over frames
    FIRST_SCORED.. (the camera moving)."""
    r = Renderer(scene, paths(seed=seed), device)
    out = [r.render_frame(f, aovs=False).color[..., :3].astype(np.float64) for f in range(FRAMES)]
    return float(np.mean([rel_mse(out[f][mask[f]], refs[f][mask[f]]) for f in range(FIRST_SCORED, FRAMES)]))


@pytest.fixture(scope="module")
def errors(device):
    scene = glass_orbit(frames=FRAMES)
    ref_r = Renderer(scene, paths(method="ris", candidates=16, taa=False, seed=5), device)
    refs = [ref_r.render_still(f, 256).color[..., :3].astype(np.float64) for f in range(FRAMES)]
    mask = sphere_pixels(device)
    assert all(0 < m.sum() < m.size for m in mask[FIRST_SCORED:])
    keep = np.array([taa_error(scene, refs, mask, 100 + s, device) for s in range(SEEDS)])
    with pytest.MonkeyPatch.context() as mp:
        built_with(mp, "GLASS_VIEW_DEPENDENT")
        drop = np.array([taa_error(scene, refs, mask, 100 + s, device) for s in range(SEEDS)])
    return keep, drop


def test_smooth_glass_keeps_its_history_and_its_mean_error_is_lower_than_without(errors):
    keep, drop = errors
    print(f"TAA relMSE on the sphere over frames {FIRST_SCORED}..{FRAMES - 1}, camera orbiting a glass sphere, "
          f"{SEEDS} seeds: "
          f"glass keeps history: mean {keep.mean():.4g} median {np.median(keep):.4g}; "
          f"glass rated as a mirror: mean {drop.mean():.4g} median {np.median(drop):.4g}")
    assert np.all(np.isfinite(keep)) and np.all(np.isfinite(drop))
    # what decides: fireflies (caustics, the reflect-or-refract branch) pass whole where the history is dropped and
    # dominate the mean; the median seed, with few of them, can favour dropping it (the ghost is real: design.md)
    assert keep.mean() < 0.5 * drop.mean(), (keep, drop)
