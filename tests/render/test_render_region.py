"""A render region (Camera.region): the camera of a part of the image sees exactly what the whole camera sees in
those pixels, for both kinds of camera, with sensor fits and shifts."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, SceneError, Settings

from ..helpers import occluder_scene


def depth(scene, device) -> np.ndarray:
    r = Renderer(scene, Settings(method="light_array", jitter=False), device)
    r.render_frame(0)
    return np.array(r.read_gbuffer()["pos"][..., 3], dtype=np.float64)


@pytest.mark.parametrize(("kind", "size", "fit", "shift"), [
    ("PERSP", (40, 30), "AUTO", (0.0, 0.0)),
    ("PERSP", (30, 40), "VERTICAL", (0.1, -0.15)),
    ("ORTHO", (40, 30), "HORIZONTAL", (-0.2, 0.1)),
])
def test_a_region_sees_what_the_whole_sees_there(device, kind, size, fit, shift):
    sc = occluder_scene(*size)
    cam = sc.camera
    cam.type, cam.sensor_fit, (cam.shift_x, cam.shift_y), cam.ortho_scale = kind, fit, shift, 7.0
    whole = depth(sc, device)
    x0, y0, x1, y1 = 7, 5, 29, 21
    sc.camera = cam.region(x0, y0, x1, y1)
    assert (sc.camera.width, sc.camera.height) == (x1 - x0, y1 - y0)
    part = depth(sc, device)
    ref = whole[y0:y1, x0:x1]
    assert np.array_equal(np.isfinite(part), np.isfinite(ref))
    hit = np.isfinite(ref)
    assert hit.mean() > 0.5
    assert np.abs(part[hit] - ref[hit]).max() < 1e-4 * np.abs(ref[hit]).max()


def test_a_region_outside_the_image_is_an_error():
    cam = occluder_scene(40, 30).camera
    with pytest.raises(SceneError, match="region"):
        cam.region(30, 0, 41, 10)
    with pytest.raises(SceneError, match="region"):
        cam.region(5, 5, 5, 10)
