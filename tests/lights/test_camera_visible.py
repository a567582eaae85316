"""Lights seen by camera rays (opencl/lights/camera_visible.h): what each shape shows, what hides it, and how a moving
one reprojects. Expected radiances are the lights' own (docs/units.md): area P / (pi A), a sphere of radius r
P / (4 pi^2 r^2), a sun of angular diameter theta S / (pi sin^2(theta / 2)); Cycles shows the same values
(tests/blender/test_lights_visible_cycles.py)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, translation
from restircl.lights.camera_visible import camera_light_indices

W, H = 64, 48
EYE = np.array([0.0, -5.0, 0.0])


def camera(frames: int = 1) -> Camera:
    cam = Camera(transforms=np.repeat(look_at(EYE, (0, 0, 0))[None], frames, axis=0), width=W, height=H)
    cam.set_fov(math.radians(50))
    return cam


def pixel(cam: Camera, p) -> tuple[int, int]:
    c = cam.transforms[0]
    rel = np.asarray(p, float) - c[:3, 3]
    x, y, z = rel @ c[:3, 0], rel @ c[:3, 1], -(rel @ c[:3, 2])
    tx, ty, _, _ = cam.tan_half_fov()
    return int((0.5 - y / z / ty * 0.5) * H), int((x / z / tx * 0.5 + 0.5) * W)


def facing(pos, towards_camera: bool = True) -> np.ndarray:
    p = np.asarray(pos, float)
    return look_at(p, p + (0, -1 if towards_camera else 1, 0))


SUN_DIR = np.array([1.5, 5.0, -0.8]) / np.linalg.norm([1.5, 5.0, -0.8])  # from the eye towards the sun


def shapes() -> list[Light]:
    """One light of each shape the camera can see, each visible to camera rays (Blender makes a light hidden)."""
    lights = [
        Light("square", "area", power=10, transforms=facing((-1.5, 0, 0.8)), size=0.5),
        Light("square_back", "area", power=10, transforms=facing((-0.5, 0, 0.8), False), size=0.5),
        Light("sphere_soft", "point", power=10, transforms=translation(0.5, 0, 0.8), radius=0.2),
        Light("sphere", "point", power=10, transforms=translation(1.5, 0, 0.8), radius=0.2, soft_falloff=False),
        Light("spot_towards", "spot", power=10, transforms=facing((-1.5, 0, -0.8)), radius=0.2),
        Light("spot_away", "spot", power=10, transforms=facing((-0.5, 0, -0.8), False), radius=0.2),
        Light("disk", "area", power=10, shape="DISK", transforms=facing((0.5, 0, -0.8)), size=0.5),
        Light("sun", "sun", power=3, angle=math.radians(10), transforms=look_at((0, 0, 0), tuple(-SUN_DIR))),
    ]
    for lt in lights:
        lt.visible_camera = True
    return lights


EXPECTED = {
    "square": 10 / (math.pi * 0.25), "square_back": 0.0, "sphere_soft": 10 / (4 * math.pi ** 2 * 0.04),
    "sphere": 10 / (4 * math.pi ** 2 * 0.04), "spot_towards": 10 / (4 * math.pi ** 2 * 0.04), "spot_away": 0.0,
    "disk": 10 / (math.pi * math.pi * 0.0625), "sun": 3 / (math.pi * math.sin(math.radians(5)) ** 2),
}


def centre(lt: Light) -> np.ndarray:
    return EYE + 10 * SUN_DIR if lt.type == "sun" else lt.transforms[0][:3, 3]


def render(scene: Scene, samples: int = 4):
    return Renderer(scene, Settings(method="reference", seed=3)).render_still(0, samples=samples)


def test_each_shape_shows_its_radiance_and_hidden_lights_show_nothing(device):
    lights = shapes()
    cam = camera()
    seen = render(Scene(lights=lights, camera=cam))
    for lt in lights:
        lt.visible_camera = False
    hidden = render(Scene(lights=lights, camera=cam))
    assert np.all(np.isfinite(seen.color)) and hidden.color[..., :3].max() == 0.0
    for lt in lights:
        r, c = pixel(cam, centre(lt))
        got = seen.color[r, c, :3]
        assert got == pytest.approx([EXPECTED[lt.name]] * 3, rel=1e-4), lt.name
        # the depth pass: a light is a surface at its distance, the sun is not
        assert math.isfinite(seen.depth[r, c]) == (EXPECTED[lt.name] > 0 and lt.type != "sun"), lt.name


def test_delta_lights_and_hidden_lights_add_no_camera_code():
    cam = camera()
    deltas = [Light("p", "point", transforms=translation(0, 0, 0)), Light("s", "sun", angle=0.0)]
    assert camera_light_indices(Scene(lights=deltas, camera=cam)) == []
    hidden = shapes()
    hidden[0].visible_camera = False
    assert camera_light_indices(Scene(lights=hidden, camera=cam)) == list(range(1, len(hidden)))


def _wall(y: float) -> Mesh:
    return Mesh("wall", vertices=[(-3, y, -3), (3, y, -3), (3, y, 3), (-3, y, 3)], triangles=[(0, 1, 2), (0, 2, 3)])


def test_the_nearer_of_light_and_geometry_wins(device):
    cam = camera()
    grey = [Material(name="grey", albedo=(0.5, 0.5, 0.5))]
    lights = [Light("behind", "area", power=10, transforms=facing((-1.5, 1.0, 0.8)), size=0.5, visible_camera=True),
              Light("front", "area", power=10, transforms=facing((1.5, -1.0, 0.8)), size=0.5, visible_camera=True),
              Light("sun", "sun", power=3, angle=math.radians(10), transforms=look_at((0, 0, 0), tuple(-SUN_DIR)),
                    visible_camera=True)]
    img = render(Scene(meshes=[_wall(0.0)], materials=grey, lights=lights, camera=cam))
    behind = img.color[pixel(cam, (-1.5, 1.0, 0.8))][:3]
    front = img.color[pixel(cam, (1.5, -1.0, 0.8))][:3]
    sun = img.color[pixel(cam, EYE + 10 * SUN_DIR)][:3]
    assert front == pytest.approx([EXPECTED["square"]] * 3, rel=1e-4)
    assert behind.max() < 1.0 and sun.max() < 1.0  # the wall: lit grey, far below either light's radiance


def test_a_moving_light_has_its_own_motion_vector(device):
    frames = 3
    step = 0.1
    lt = Light("moving", "area", power=10, size=0.5, visible_camera=True,
               transforms=np.stack([facing((step * f, 0, 0)) for f in range(frames)]))
    cam = camera(frames)
    r = Renderer(Scene(lights=[lt], camera=cam), Settings(method="reference", seed=1))
    assert "motion" in r.features
    r.render_frame(0)
    f1 = r.render_frame(1)
    row, col = pixel(cam, (step, 0, 0))
    tx = cam.tan_half_fov()[0]
    px_per_m = W / (2 * tx * 5.0)  # the light's plane is 5 m from the eye
    assert f1.vector[row, col, 0] == pytest.approx(-step * px_per_m, rel=0.02)  # towards where it was
    assert f1.vector[row, col, 2] == pytest.approx(step * px_per_m, rel=0.02)  # and where it goes next
    assert abs(f1.vector[row, col, 1]) < 1e-3


def test_taa_leaves_no_trail_behind_a_moving_light(device):
    """A light pixel reprojects only onto a light: where the light was last frame and is no longer, the history
    (the light's radiance) is rejected, and the black background shows at once, also next to the light's edge
    (where clipping to the neighbourhood alone would keep some of it)."""
    frames, step = 6, 0.25
    lt = Light("moving", "area", power=10, size=0.5, visible_camera=True,
               transforms=np.stack([facing((step * f - 0.5, 0, 0)) for f in range(frames)]))
    cam = camera(frames)
    r = Renderer(Scene(lights=[lt], camera=cam), Settings(method="restir", seed=1, jitter=False))
    covered_before = None
    for f in range(frames):
        out = r.render_frame(f)
        covered = np.isfinite(out.depth)
        if covered_before is not None:
            trail = covered_before & ~covered
            assert trail.sum() >= 8 and out.color[trail][:, :3].max() < 1e-3, f
            # the light's own pixels follow it: exact inside; along its edges the neighbourhood clip (a 3x3 half
            # black) takes a little, as it does at any moving surface's edge
            inner = covered.copy()
            inner[1:-1, 1:-1] &= covered[:-2, 1:-1] & covered[2:, 1:-1] & covered[1:-1, :-2] & covered[1:-1, 2:]
            seen = out.color[..., 0] / EXPECTED["square"]
            assert inner.sum() >= 8 and np.all(np.abs(seen[inner] - 1) < 1e-3), f
            assert np.all(np.abs(seen[covered] - 1) < 0.1), f
        covered_before = covered
