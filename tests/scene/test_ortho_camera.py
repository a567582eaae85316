"""The orthographic camera: its rays are parallel and land where an independent (numpy) orthographic projection
of Blender's rules puts them; motion vectors between two orthographic views, and between a perspective and an
orthographic one (the viewport's numpad-5 toggle), are exact; bad parameters are refused by name; the scene file
keeps the type."""
import numpy as np
import pytest
from restircl import Camera, Renderer, Scene, SceneError, Settings, look_at, scenes
from restircl.core.layouts import float_bits_to_int

W, H = 48, 32


def axes(m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(origin, right, up, forward) of a Blender camera matrix (looks along its local -Z)."""
    m = np.asarray(m, np.float64)
    right, up, back = (m[:3, i] / np.linalg.norm(m[:3, i]) for i in range(3))
    return m[:3, 3], right, up, -back


def blender_ortho_pixels(cam: Camera, p: np.ndarray) -> np.ndarray:
    """Pixel coordinates (row 0 at the top) of world points under Blender's orthographic rules: ortho_scale spans
    the fitted dimension (the larger one under AUTO), the shift is a fraction of it."""
    o, right, up, _ = axes(cam.transforms[0])
    fit = cam.sensor_fit if cam.sensor_fit != "AUTO" else ("HORIZONTAL" if cam.width >= cam.height else "VERTICAL")
    aspect = cam.width / cam.height
    span_x = cam.ortho_scale if fit == "HORIZONTAL" else cam.ortho_scale * aspect
    span_y = span_x / aspect
    d = p - o
    x = d @ right - cam.shift_x * cam.ortho_scale
    y = d @ up - cam.shift_y * cam.ortho_scale
    return np.stack([(x / span_x + 0.5) * cam.width, (0.5 - y / span_y) * cam.height], -1)


def blender_persp_pixels(cam: Camera, p: np.ndarray) -> np.ndarray:
    o, right, up, fwd = axes(cam.transforms[0])
    fit = cam.sensor_fit if cam.sensor_fit != "AUTO" else ("HORIZONTAL" if cam.width >= cam.height else "VERTICAL")
    sensor = cam.sensor_width if cam.sensor_fit in ("AUTO", "HORIZONTAL") else cam.sensor_height
    aspect = cam.width / cam.height
    span_x = sensor / cam.lens if fit == "HORIZONTAL" else sensor / cam.lens * aspect  # at unit distance
    span_y = span_x / aspect
    d = p - o
    z = d @ fwd
    x = (d @ right) / z - cam.shift_x * sensor / cam.lens
    y = (d @ up) / z - cam.shift_y * sensor / cam.lens
    return np.stack([(x / span_x + 0.5) * cam.width, (0.5 - y / span_y) * cam.height], -1)


def ortho_camera(eye=(0.3, -4.0, 3.0), scale: float = 5.0, fit: str = "AUTO", shift=(0.0, 0.0)) -> Camera:
    return Camera(look_at(eye, (0.0, 0.0, 0.3)), W, H, type="ORTHO", ortho_scale=scale, sensor_fit=fit,
                  shift_x=shift[0], shift_y=shift[1])


def gbuffer(r: Renderer) -> np.ndarray:
    return r.read_gbuffer()


def two_views(scene, device, prev: Camera, cur: Camera):
    """Render view `prev`, then `cur`: (renderer, G-buffer, hit mask, hit positions, previous pixel positions
    that the motion vectors give)."""
    scene.camera = prev
    r = Renderer(scene, Settings(method="light_array", jitter=False), device, interactive=True)
    r.render_view(prev)
    r.render_view(cur)
    g = gbuffer(r)
    hit = float_bits_to_int(g["normal"][..., 3]) >= 0
    ys, xs = np.mgrid[0:H, 0:W]
    got = np.stack([xs + 0.5, ys + 0.5], -1) + g["motion"][..., :2]
    return r, g, hit, g["pos"][..., :3].astype(np.float64), got


@pytest.fixture(scope="module")
def scene():
    return scenes.moving_box(W, H, frames=1)


@pytest.mark.parametrize("fit,shift", [("AUTO", (0.0, 0.0)), ("VERTICAL", (0.1, -0.05)), ("HORIZONTAL", (0, 0.2))])
def test_orthographic_rays_land_where_blender_projects(device, scene, fit, shift):
    cam = ortho_camera(fit=fit, shift=shift)
    scene.camera = cam
    r = Renderer(scene, Settings(method="light_array", jitter=False), device)
    frame = r.render_frame(0)
    assert np.all(np.isfinite(frame.color))
    g = gbuffer(r)
    hit = float_bits_to_int(g["normal"][..., 3]) >= 0
    assert hit.sum() > 0.8 * W * H
    pos = g["pos"][..., :3].astype(np.float64)
    ys, xs = np.mgrid[0:H, 0:W]
    centres = np.stack([xs + 0.5, ys + 0.5], -1)
    assert np.abs(blender_ortho_pixels(cam, pos) - centres)[hit].max() < 2e-3
    o, _, _, fwd = axes(cam.transforms[0])
    np.testing.assert_allclose(g["pos"][..., 3][hit], ((pos - o) @ fwd)[hit], rtol=1e-5)
    # the flat floor seen along one direction: its depth is an affine function of the pixel (a perspective
    # camera's would be hyperbolic), so its second differences along a row vanish
    floor = hit & (float_bits_to_int(g["albedo"][..., 3]) == 0)
    depth = np.where(floor, g["pos"][..., 3], np.nan)
    second = np.abs(np.diff(depth, 2, axis=1))
    assert np.isfinite(second).sum() > W * H / 2 and np.nanmax(second) < 1e-4


def test_motion_between_orthographic_views_is_exact(device, scene):
    a = ortho_camera(eye=(0.3, -4.0, 1.0), scale=5.0)
    b = ortho_camera(eye=(0.5, -4.1, 1.1), scale=4.6, shift=(0.03, 0.0))
    r, g, hit, pos, got = two_views(scene, device, a, b)
    o, _, _, fwd = axes(a.transforms[0])
    seen = (pos - o) @ fwd > 0  # in front of the previous view's plane: it has a previous position
    assert np.all((g["motion"][..., 2] == 1.0)[hit] == seen[hit]) and (hit & seen).sum() > 0.8 * hit.sum()
    ok = hit & seen
    err = np.abs(got - blender_ortho_pixels(a, pos))[ok]
    assert err.max() < 2e-3, err.max()
    np.testing.assert_allclose(g["motion"][..., 3][ok], ((pos - o) @ fwd)[ok], rtol=1e-4)
    # the background of two orthographic views: the same direction at every pixel, history kept in place
    miss = ~hit
    assert miss.sum() > 0
    assert np.all(g["motion"][..., 2][miss] == 1.0) and np.all(g["motion"][..., :2][miss] == 0.0)


def test_motion_from_perspective_to_orthographic_view(device, scene):
    """The viewport's numpad-5 toggle: the previous frame was perspective, this one orthographic."""
    persp = Camera(look_at((0.3, -4.0, 1.0), (0.0, 0.0, 0.3)), W, H, lens=30.0, shift_x=0.05)
    ortho = ortho_camera(eye=(0.3, -4.0, 1.0), scale=5.0)
    r, g, hit, pos, got = two_views(scene, device, persp, ortho)
    ok = hit & (g["motion"][..., 2] == 1.0)
    assert ok.sum() > 0.8 * hit.sum()
    assert np.abs(got - blender_persp_pixels(persp, pos))[ok].max() < 2e-3
    # and back: a perspective view finds no history for the background an orthographic camera saw
    r.render_view(persp)
    g = gbuffer(r)
    miss = float_bits_to_int(g["normal"][..., 3]) < 0
    assert miss.sum() > 0 and np.all(g["motion"][..., 2][miss] == 0.0)


def test_bad_orthographic_parameters_are_refused(scene):
    for kwargs, word in (({"type": "PANO"}, "type"), ({"ortho_scale": 0.0}, "ortho_scale"),
                         ({"ortho_scale": float("nan")}, "ortho_scale")):
        cam = ortho_camera()
        for k, v in kwargs.items():
            setattr(cam, k, v)
        scene.camera = cam
        with pytest.raises(SceneError, match=word):
            scene.validate()


def test_scene_file_keeps_the_orthographic_camera(tmp_path, scene):
    scene.camera = ortho_camera(scale=3.5)
    scene.save(tmp_path / "s.npz")
    back = Scene.load(tmp_path / "s.npz").camera
    assert (back.type, back.ortho_scale) == ("ORTHO", 3.5)
    assert back.view_plane() == scene.camera.view_plane()
