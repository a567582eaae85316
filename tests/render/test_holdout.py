"""Holdout objects (Mesh.holdout, HAS_HOLDOUT): camera rays that meet one see a hole (colour 0, Frame.holdout set),
while the rest of the image, the holdout's shadow included, is what it is without the flag."""

from __future__ import annotations

import numpy as np
from restircl import Renderer, Settings

from ..helpers import occluder_scene


def render(device, holdout: bool):
    sc = occluder_scene(32, 24)
    sc.meshes[1].holdout = holdout  # the blocks
    r = Renderer(sc, Settings(method="light_array", jitter=False), device)
    return r, r.render_still(0, 4)


def test_a_holdout_is_a_hole_that_still_casts_its_shadow(device):
    r0, plain = render(device, False)
    r1, held = render(device, True)
    assert not r0.flags["HAS_HOLDOUT"] and r1.flags["HAS_HOLDOUT"]
    blocks = np.isfinite(plain.depth) & ~np.isfinite(held.depth)
    assert held.holdout is not None and np.array_equal(held.holdout, blocks)
    assert 0.05 < blocks.mean() < 0.6
    assert not plain.holdout.any()
    assert np.all(held.color[blocks][:, :3] == 0.0) and plain.color[blocks][:, :3].mean() > 0.01
    # elsewhere the same image: the same samples, the blocks still shadowing the floor
    assert np.array_equal(held.color[~blocks], plain.color[~blocks])



def test_a_still_counts_the_share_of_its_samples_that_met_the_hole(device):
    """Frame.holdout_shares (opencl/still/holdout.cl): without jitter every sample sees the pixel's centre, so the
    shares are the last G-buffer's hole and miss masks; with jitter the hole's edge pixels get a share between 0
    and 1, and the hole's total share stays its area."""
    sc = occluder_scene(32, 24)
    sc.meshes[1].holdout = True
    fixed = Renderer(sc, Settings(method="light_array", jitter=False), device).render_still(0, 4)
    assert fixed.holdout_shares is not None and fixed.holdout_shares.shape == (24, 32, 2)
    assert fixed.holdout is not None and fixed.depth is not None
    assert np.array_equal(fixed.holdout_shares[..., 0], fixed.holdout.astype(np.float32))
    assert np.array_equal(fixed.holdout_shares[..., 1], (~np.isfinite(fixed.depth) & ~fixed.holdout).astype(np.float32))
    jittered = Renderer(sc, Settings(method="light_array"), device).render_still(0, 32).holdout_shares
    assert jittered is not None
    hole = jittered[..., 0]
    edge = (hole > 0) & (hole < 1)
    assert 8 <= edge.sum() and np.all(jittered.sum(axis=-1) <= 1.0 + 1e-6)
    assert np.all(hole[edge] * 32 == np.round(hole[edge] * 32))  # counts of 32 samples
    assert abs(hole.mean() - fixed.holdout.mean()) < 0.02  # the same area, spread over its edge
    # away from the edge (no pixel of the other mask within one pixel) the shares are what the centre sees
    inside = fixed.holdout.copy()
    for axis in (0, 1):
        for shift in (-1, 1):
            inside &= np.roll(fixed.holdout, shift, axis)
    inside[[0, -1], :] = False  # np.roll wraps around
    inside[:, [0, -1]] = False
    assert inside.sum() >= 8 and np.all(hole[inside] == 1.0)
    without = Renderer(occluder_scene(32, 24), Settings(method="light_array"), device).render_still(0, 2)
    # no holdout: no sample names one; the world's share is still counted (a transparent film's alpha)
    assert without.holdout_shares is not None and without.depth is not None
    assert np.all(without.holdout_shares[..., 0] == 0)
    world, missed = without.holdout_shares[..., 1], ~np.isfinite(without.depth)  # missed: by the last sample
    assert np.all(world * 2 == np.round(world * 2))  # counts of 2 samples
    assert np.all(world[missed] >= 0.5) and np.all(world[~missed] <= 0.5) and 0.1 < missed.mean() < 0.9
