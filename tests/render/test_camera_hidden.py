"""Objects hidden from the camera (Mesh.camera_visible off, HAS_CAMERA_HIDDEN): camera rays pass through them to
what lies behind, and everything else, their shadows included, is what it is with them seen."""

from __future__ import annotations

import numpy as np
from restircl import Renderer, Settings, translation

from ..helpers import occluder_scene


def render(device, hidden: bool, without: bool = False):
    sc = occluder_scene(32, 24)
    # lifted off the floor: a hidden face in the floor's plane would let the ray pass the floor too (camera/hidden.h)
    sc.meshes[1].transforms = translation(0.0, 0.0, 0.05)
    if without:
        del sc.meshes[1]  # the blocks
    else:
        sc.meshes[1].camera_visible = not hidden
    r = Renderer(sc, Settings(method="light_array", jitter=False), device)
    return r, r.render_still(0, 4)


def test_camera_rays_pass_through_a_hidden_object_that_still_casts_its_shadow(device):
    r0, seen = render(device, False)
    r1, hidden = render(device, True)
    _, gone = render(device, False, without=True)
    assert not r0.flags["HAS_CAMERA_HIDDEN"] and r1.flags["HAS_CAMERA_HIDDEN"]
    blocks = seen.depth < gone.depth - 1e-3  # where the blocks stand in front of the floor
    assert 0.05 < blocks.mean() < 0.6
    # behind the blocks: the floor, at the floor's depth
    assert np.allclose(hidden.depth, gone.depth, rtol=1e-4)
    # the floor keeps the blocks' shadows: where the camera saw the floor anyway the image is the seen one
    assert np.array_equal(hidden.color[~blocks], seen.color[~blocks])
    assert not np.allclose(hidden.color[~blocks], gone.color[~blocks])
