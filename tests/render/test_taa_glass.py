"""Smooth glass under a moving camera (docs/design.md, "Glass under motion"): the primary hit of a pixel seen through
glass is the glass surface, and its motion vector is that surface's motion. What the glass shows moves with the view
instead, so reprojected history shows it where it was (a ghost); surface/view_dependence.h rates glass as it rates a
mirror, so TAA shortens and clips that history. It used to leave glass out (keep its history): one path per frame
through glass then carried fireflies (the reflect-or-refract branch picked by the macroscopic normal's Fresnel) that
cost more than the ghost; with the branch picked at the sampled microfacet they are gone and the ghost decides
(docs/measurements/temporal-stability.md, "Glass under motion"). GLASS_KEEPS_HISTORY leaves glass out again: the
negative control."""

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.eval.scenes.glass_orbit import glass_orbit

from ..bias_controls import built_with
from ..helpers import rel_mse

FRAMES, FIRST_SCORED, SEEDS = 12, 4, 8
# The references' samples per frame: they cost most of this file. The TAA outputs' errors are far above the
# references' noise: with 64, 128 and 256 the ratio of the two means below was 0.31, 0.30 and 0.32 (bound 0.5;
# docs/measurements/benchmarks.md, "Test suite time")
REF_SPP = 64
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
    refs = [ref_r.render_still(f, REF_SPP).color[..., :3].astype(np.float64) for f in range(FRAMES)]
    mask = sphere_pixels(device)
    assert all(0 < m.sum() < m.size for m in mask[FIRST_SCORED:])
    mirror = np.array([taa_error(scene, refs, mask, 100 + s, device) for s in range(SEEDS)])
    with pytest.MonkeyPatch.context() as mp:
        built_with(mp, "GLASS_KEEPS_HISTORY")
        keep = np.array([taa_error(scene, refs, mask, 100 + s, device) for s in range(SEEDS)])
    return mirror, keep


def test_smooth_glass_is_rated_as_a_mirror_and_its_error_is_lower_than_keeping_its_history(errors):
    mirror, keep = errors
    print(f"TAA relMSE on the sphere over frames {FIRST_SCORED}..{FRAMES - 1}, camera orbiting a glass sphere, "
          f"{SEEDS} seeds: "
          f"glass rated as a mirror: mean {mirror.mean():.4g} median {np.median(mirror):.4g}; "
          f"glass keeps history: mean {keep.mean():.4g} median {np.median(keep):.4g}; per seed {np.round(mirror, 3)}"
          f" and {np.round(keep, 3)}")
    assert np.all(np.isfinite(keep)) and np.all(np.isfinite(mirror))
    # measured when written: mirror mean 1.48 (median 1.36), keeping the history 4.51 (4.47): the ghost; against
    # references of REF_SPP = 64 samples (2026-12-06): 1.59 (1.48) and 5.13 (5.10)
    assert mirror.mean() < 0.5 * keep.mean(), (mirror, keep)
