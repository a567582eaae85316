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
