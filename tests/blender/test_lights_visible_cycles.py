"""Lights seen by the camera against Cycles (direct light only): every shape (square, rectangle, disk, ellipse from
the front and the back, spheres with and without soft falloff, spots from inside and outside their cone, a sun
with an angle) in front of a lit wall, with Ray Visibility > Camera on, and with it off. Both renders go through
restircl.eval.cycles.bridge.to_bpy, which sets each light object's visible_camera from Light.visible_camera."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl import (  # noqa: E402
    Light,
    Material,
    Mesh,
    Renderer,
    Scene,
    Settings,
    look_at,
    translation,
)
from restircl.eval.cycles import bridge as cycles  # noqa: E402

from ..lights.test_camera_visible import SUN_DIR, camera, facing  # noqa: E402

pytestmark = pytest.mark.blender

BOUND = 0.01  # relMSE, as tests/blender/test_blender_cycles.py


def scene(visible: bool) -> Scene:
    wall = Mesh("wall", vertices=[(-4, 2, -3), (4, 2, -3), (4, 2, 3), (-4, 2, 3)], triangles=[(0, 1, 2), (0, 2, 3)])
    lights = [
        Light("square", "area", power=10, transforms=facing((-1.6, 0, 0.9)), size=0.4),
        Light("rect_back", "area", power=10, shape="RECTANGLE", transforms=facing((-0.8, 0, 0.9), False),
              size=0.5, size_y=0.3),
        Light("rect", "area", power=10, shape="RECTANGLE", transforms=facing((0.0, 0, 0.9)), size=0.5, size_y=0.3),
        Light("ellipse", "area", power=10, shape="ELLIPSE", transforms=facing((0.8, 0, 0.9)), size=0.5, size_y=0.3),
        Light("disk", "area", power=10, shape="DISK", transforms=facing((1.6, 0, 0.9)), size=0.4),
        Light("sphere_soft", "point", power=10, transforms=translation(-1.6, 0, -0.9), radius=0.2),
        Light("sphere", "point", power=10, transforms=translation(-0.8, 0, -0.9), radius=0.2, soft_falloff=False),
        Light("spot_in", "spot", power=10, transforms=look_at((0.0, 0, -0.9), (0.0, -5, -0.6)), radius=0.2,
              spot_size=math.radians(30), spot_blend=0.5),
        Light("spot_out", "spot", power=10, transforms=facing((0.8, 0, -0.9), False), radius=0.2),
        Light("sun", "sun", power=0.5, angle=math.radians(15), transforms=look_at((0, 0, 0), tuple(-SUN_DIR))),
    ]
    for lt in lights:
        lt.visible_camera = visible
    return Scene(meshes=[wall], materials=[Material(name="grey", albedo=(0.5, 0.5, 0.5))], lights=lights,
                 camera=camera())


@pytest.mark.parametrize("visible", [True, False], ids=["camera_on", "camera_off"])
def test_lights_seen_by_the_camera_agree_with_cycles(visible, record_property):
    sc = scene(visible)
    cyc = cycles.render(cycles.to_bpy(sc), samples=256, seed=1, threads=2).image
    ours = Renderer(sc, Settings(method="reference", seed=2)).render_still(0, samples=256).color[..., :3]
    err = float(np.mean((ours - cyc) ** 2 / (cyc ** 2 + 0.01)))
    ratio = float(ours.sum() / cyc.sum())
    record_property("relmse", err)
    print(f"camera {'on' if visible else 'off'}: relMSE {100 * err:.3f} %  sum ours/cycles {ratio:.4f}")
    assert err < BOUND and ratio == pytest.approx(1.0, abs=0.01)
    bright = float(cyc.max())
    assert (bright > 20) == visible  # the lights' own radiance (tens) is in the image only when seen
    assert np.all(np.isfinite(ours))
