"""FrameRegion (farm/region.py): a region's frame placed in the full frame (empty elsewhere: 0, depth infinite) or
written alone (crop), and the camera of the region."""

from __future__ import annotations

import numpy as np
from restircl import Camera
from restircl.farm.region import FrameRegion
from restircl.render.frame import Frame
from restircl.scene.scene import Scene


def region_frame() -> Frame:
    color = np.arange(3 * 2 * 4, dtype=np.float32).reshape(3, 2, 4) + 1.0
    depth = np.full((3, 2), 2.5, np.float32)
    return Frame(color=color, noisy=color[..., :3].copy(), depth=depth, normal=None, vector=None, albedo=None,
                 stage_ms={"primary": 1.0}, light_groups={"key": color[..., :3] * 2})


def test_a_placed_frame_is_empty_outside_the_region():
    reg = FrameRegion(x=1, top=2, width=2, height=3, full_width=5, full_height=6, crop=False)
    f = region_frame()
    out = reg.place(f)
    assert out.color.shape == (6, 5, 4) and out.noisy.shape == (6, 5, 3) and out.depth.shape == (6, 5)
    assert np.array_equal(out.color[2:5, 1:3], f.color)
    assert out.color[0:2].sum() == 0 and out.color[5:].sum() == 0 and out.color[:, [0, 3, 4]].sum() == 0
    assert np.all(out.depth[2:5, 1:3] == 2.5) and np.isinf(out.depth).sum() == 30 - 6
    assert out.light_groups is not None and np.array_equal(out.light_groups["key"][2:5, 1:3], 2 * f.noisy)
    assert out.stage_ms == {"primary": 1.0} and out.normal is None
    assert FrameRegion(1, 2, 2, 3, 5, 6, crop=True).place(f) is f  # crop: the region's own frame


def test_the_region_camera_sees_the_region_alone():
    cam = Camera(np.eye(4), 64, 48, lens=35.0)
    reg = FrameRegion(x=16, top=24, width=32, height=20, full_width=64, full_height=48, crop=False)
    scene = reg.apply(Scene([], [], [], cam))
    assert scene.camera is not None and (scene.camera.width, scene.camera.height) == (32, 20)
    whole_tx, whole_ty, _, _ = cam.view_plane()
    tx, ty, sx, sy = scene.camera.view_plane()
    # half the plane: 32 of 64 columns, 20 of 48 rows; centred on column 32 (the axis) and row 34 (10 below it)
    assert np.isclose(tx, whole_tx / 2) and np.isclose(ty, whole_ty * 20 / 48)
    assert np.isclose(sx, 0.0, atol=1e-12) and np.isclose(sy, -whole_ty * 10 / 24)
