"""An orthographic Blender camera: exported with Blender's own projection (world_to_camera_view) for every sensor
fit and shift, and rendered by F12 into finite passes whose depth is the distance to the camera's plane."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered, needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = pytest.mark.blender
ensure_registered()


@pytest.mark.parametrize(("res", "fit", "shift"), [
    ((64, 48), "AUTO", (0.0, 0.0)),
    ((48, 64), "AUTO", (0.1, -0.2)),
    ((64, 48), "VERTICAL", (0.0, 0.15)),
    ((80, 40), "HORIZONTAL", (0.2, 0.1)),
])
def test_orthographic_projection_matches_blender(res, fit, shift):
    from bpy_extras.object_utils import world_to_camera_view
    from mathutils import Vector
    from restircl_blender import export as ex

    sc = scenes.new_scene(*res)
    scenes.quad("Floor", 10.0, 10.0)
    cam = scenes.camera((1.0, -5.0, 3.0), (0.3, 0.5, 0.2), type="ORTHO", ortho_scale=4.5, sensor_fit=fit,
                        shift_x=shift[0], shift_y=shift[1])
    c = ex.export_scene(bpy.context.evaluated_depsgraph_get(), None, frame_set=sc.frame_set).scene.camera
    assert (c.type, c.ortho_scale) == ("ORTHO", pytest.approx(4.5))
    hx, hy, sx, sy = c.view_plane()
    m = c.transforms[0]
    rng = np.random.default_rng(2)
    for p in rng.uniform((-3, -3, -1), (3, 3, 2), size=(20, 3)):
        d = np.linalg.inv(m) @ np.append(p, 1.0)
        uvw = world_to_camera_view(sc, cam, Vector(p))
        assert ((d[0] - sx) / hx + 1) / 2 == pytest.approx(uvw.x, abs=1e-5)
        assert ((d[1] - sy) / hy + 1) / 2 == pytest.approx(uvw.y, abs=1e-5)


@needs_renderer
def test_orthographic_still_render(tmp_path):
    w, h = 48, 32
    sc = scenes.new_scene(w, h, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("Red", (0.8, 0.2, 0.1)), location=(0.3, 0, 0.4))
    scenes.light("POINT", "Point", (-1.0, -0.5, 1.5), energy=60.0)
    scenes.camera((0.0, 0.0, 6.0), (0.0, 0.0, 0.0), type="ORTHO", ortho_scale=4.0)  # straight down
    sc.view_layers[0].use_pass_z = True
    sc.restircl.samples = 4
    render_to(sc, tmp_path / "ortho.exr")
    p = read_exr_passes(tmp_path / "ortho.exr")
    rgb, depth = p["Combined"][..., :3], p["Depth"][..., 0]
    assert rgb.shape == (h, w, 3) and np.all(np.isfinite(rgb)) and rgb.mean() > 0.01
    # looking straight down, the floor is 6 from the camera's plane at every pixel it fills (a perspective
    # camera's distance would grow towards the corners); the box top is at 0.8
    floor = np.abs(depth - 6.0) < 1e-3
    top = np.abs(depth - (6.0 - 0.8)) < 1e-3
    assert floor.mean() > 0.7 and top.sum() > 0
    assert math.isclose(float(depth[0, 0]), 6.0, rel_tol=1e-4) and math.isclose(float(depth[-1, -1]), 6.0,
                                                                                 rel_tol=1e-4)
