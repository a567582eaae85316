"""The viewport session, headless (bpy in background has no GPU drawing), driven with the matrices a 3D view
gives: frames are finite and stop at the sample limit; perspective and orthographic views land where the view's
own matrices project (numpy); an orbit keeps the history (its length grows through the motion) while a cut-like
jump resets it; an edit of one object uploads only what it changed; the worker stops cleanly."""

from __future__ import annotations

import dataclasses
import math
import threading
import time

import numpy as np
import pytest

pytest.importorskip("bpy")  # the add-on package imports bpy (the session module itself does not use it)

from .test_blender_support import ensure_registered  # noqa: E402  (makes restircl_blender importable)

ensure_registered()

from restircl import Settings, look_at, scenes  # noqa: E402
from restircl.core.layouts import float_bits_to_int  # noqa: E402
from restircl_blender.viewport_edit import SceneEdit  # noqa: E402
from restircl_blender.viewport_session import ViewportSession, scaled_size, view_camera  # noqa: E402

W, H = 40, 30
TARGET = np.array([0.0, 0.0, 0.3])


def perspective(tan_x: float, shift=(0.0, 0.0), near=0.1, far=100.0) -> np.ndarray:
    """An OpenGL-style projection as Blender's RegionView3D.window_matrix has it (shift: the camera view's
    offset, in NDC)."""
    tan_y = tan_x * H / W
    p = np.zeros((4, 4))
    p[0, 0], p[1, 1] = 1.0 / tan_x, 1.0 / tan_y
    p[0, 2], p[1, 2] = shift
    p[2, 2], p[2, 3] = -(far + near) / (far - near), -2 * far * near / (far - near)
    p[3, 2] = -1.0
    return p


def orthographic(half_x: float, offset=(0.0, 0.0), near=-50.0, far=50.0) -> np.ndarray:
    half_y = half_x * H / W
    p = np.eye(4)
    p[0, 0], p[1, 1] = 1.0 / half_x, 1.0 / half_y
    p[0, 3], p[1, 3] = offset
    p[2, 2], p[2, 3] = -2.0 / (far - near), -(far + near) / (far - near)
    return p


def orbit_view(angle_deg: float, radius: float = 4.5, height: float = 2.5) -> np.ndarray:
    """The view matrix (world to view) of an orbit around TARGET."""
    a = math.radians(angle_deg)
    eye = TARGET + (radius * math.sin(a), -radius * math.cos(a), height)
    return np.linalg.inv(look_at(tuple(eye), tuple(TARGET)))


def session(scene=None, samples: int = 1, **kw) -> ViewportSession:
    scene = scene or scenes.moving_box(W, H, frames=1)
    s = Settings(**kw.pop("settings", {}))
    return ViewportSession(scene, s, samples=samples, track_history=True, **kw).start()


def step(sess: ViewportSession, view, proj, index: int):
    sess.set_view(view_camera(view, proj, W, H))
    frame = sess.wait(index)
    assert sess.error is None, sess.error
    assert frame is not None and frame.index >= index
    return frame


def test_frames_are_finite_and_stop_at_the_sample_limit():
    redraws = []
    sess = session(samples=5, on_frame=lambda: redraws.append(threading.current_thread().name))
    try:
        frame = step(sess, orbit_view(0), perspective(0.5), 5)
        assert frame.samples == 5 and frame.rgba.shape == (H, W, 4)
        assert np.all(np.isfinite(frame.rgba)) and frame.rgba[..., :3].mean() > 0.01
        time.sleep(0.5)  # the view is still and the limit reached: the worker sleeps
        assert sess.stats.frames == 5 and sess.latest().index == 5
        assert set(redraws) == {"restircl-viewport"}  # never on the caller's thread
        assert "sample 5/5" in sess.status_text() and "ms/frame" in sess.status_text()
        assert sess.device_label and sess.status_text().endswith(f"| {sess.device_label}")  # the device
    finally:
        assert sess.stop()


@pytest.mark.parametrize("kind", ["persp", "ortho"])
def test_views_land_where_their_matrices_project(kind):
    view = orbit_view(20)
    proj = perspective(0.45, shift=(0.1, -0.05)) if kind == "persp" else orthographic(2.5, offset=(0.1, 0.05))
    sess = session(settings={"method": "light_array", "jitter": False})
    try:
        step(sess, view, proj, 1)
        r = sess.renderer
        g = r.read_gbuffer()
    finally:
        assert sess.stop()
    hit = float_bits_to_int(g["normal"][..., 3]) >= 0
    assert hit.mean() > 0.5
    p = np.concatenate([g["pos"][..., :3].astype(np.float64), np.ones((H, W, 1))], -1)
    clip = p @ (proj @ view).T
    ndc = clip[..., :2] / clip[..., 3:]
    px = np.stack([(ndc[..., 0] + 1) * 0.5 * W, (1 - ndc[..., 1]) * 0.5 * H], -1)
    ys, xs = np.mgrid[0:H, 0:W]
    err = np.abs(px - np.stack([xs + 0.5, ys + 0.5], -1))[hit]
    assert err.max() < 2e-3, err.max()


def test_an_orthographic_view_starts_its_rays_at_the_scene():
    """Blender's orthographic view sees behind its origin (clip_end / 2 back); the session moves the rays' start
    forward to the scene's bounding box: the same hits, depths measured from near the scene."""
    view, proj = orbit_view(10), orthographic(2.5)
    gbufs = []
    for back in (50.0, 500.0):
        sess = session(settings={"method": "light_array", "jitter": False})
        try:
            sess.set_view(view_camera(view, proj, W, H, ortho_back=back))
            assert sess.wait(1) is not None and sess.error is None, sess.error
            r = sess.renderer
            gbufs.append(r.read_gbuffer())
        finally:
            assert sess.stop()
    hit = float_bits_to_int(gbufs[0]["normal"][..., 3]) >= 0
    assert hit.mean() > 0.5
    assert np.array_equal(hit, float_bits_to_int(gbufs[1]["normal"][..., 3]) >= 0)
    np.testing.assert_allclose(gbufs[0]["pos"][..., :3][hit], gbufs[1]["pos"][..., :3][hit], atol=1e-3)
    np.testing.assert_allclose(gbufs[0]["pos"][..., 3][hit], gbufs[1]["pos"][..., 3][hit], atol=1e-3)
    assert gbufs[1]["pos"][..., 3][hit].max() < 20.0  # the scene is 12 m across, not 500 m away


def test_an_orbit_keeps_history_and_a_jump_resets_it():
    sess = session()
    try:
        lengths = [step(sess, orbit_view(2.0 * k), perspective(0.5), k + 1).history for k in range(12)]
        assert sess.stats.cuts == 1  # the first frame only
        assert all(b > a for a, b in zip(lengths[1:], lengths[2:], strict=False)), lengths
        assert lengths[-1] > 6.0, lengths  # most pixels kept their history through 22 degrees of orbit
        jumped = step(sess, orbit_view(22.0 + 90.0), perspective(0.5), 13)  # a numpad view: 90 degrees at once
        assert jumped.cut and jumped.history == 1.0 and sess.stats.cuts == 2
        # orthographic from here (numpad 5): reprojected, not a cut, and an orthographic orbit (whose view origin
        # Blender puts clip_end / 2 behind) keeps its history too
        sess.set_view(view_camera(orbit_view(112.0), orthographic(2.5), W, H, ortho_back=500.0))
        ortho = sess.wait(14)
        assert not ortho.cut and ortho.history > 1.2
        sess.set_view(view_camera(orbit_view(114.0), orthographic(2.5), W, H, ortho_back=500.0))
        orbit = sess.wait(15)
        assert not orbit.cut and orbit.history > ortho.history
        assert np.all(np.isfinite(ortho.rgba)) and np.all(np.isfinite(orbit.rgba))
    finally:
        assert sess.stop()


def test_an_edit_of_one_object_uploads_only_what_changed():
    scene = scenes.moving_box(W, H, frames=1)
    sess = session(scene, samples=4)
    try:
        step(sess, orbit_view(0), perspective(0.5), 4)
        sess.sample_limit = 1  # from here one frame per edit, then the worker sleeps (the G-buffer is read)
        ds = sess.renderer.device_scene
        before = dict(ds.uploads)
        box = next(m for m in sess.scene.meshes if m.name == "box")
        moved = box.transforms[0] @ np.array([[1, 0, 0, 0.15], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])
        sess.edit(SceneEdit(transforms={"box": moved}))
        frame = sess.wait(5)
        assert sess.stats.edits == {"kept": 1}
        assert ds.uploads == {**before, "geometry": before["geometry"] + 1}  # not the materials, not the lights
        assert not frame.cut and frame.history > 3.0  # the history survived the move
        # the moved box's pixels point back to where it was: M_before M_after^-1 in the motion rows
        r = sess.renderer
        g = r.read_gbuffer()
        obj = float_bits_to_int(g["albedo"][..., 3])
        hit = float_bits_to_int(g["normal"][..., 3]) >= 0
        on_box, on_floor = hit & (obj == 1), hit & (obj == 0)
        assert on_box.sum() > 5
        assert np.abs(g["motion"][..., :2][on_floor]).max() < 1e-3
        assert np.median(g["motion"][..., 0][on_box]) < -0.3  # it moved +x: its old place is to the left
        # a light's colour: the lights only
        edited = scenes.moving_box(W, H, frames=1)
        edited.meshes[1].transforms = np.asarray(moved)[None]
        edited.lights[1].color = (0.2, 0.4, 1.0)
        base = dict(ds.uploads)
        sess.edit(SceneEdit(scene=edited))
        frame = sess.wait(6)
        assert ds.uploads == {**base, "lights": base["lights"] + 1} and not frame.cut
        # the same through the lights alone (what view_update sends for a light edit): its power
        lights = [dataclasses.replace(lt) for lt in edited.lights]
        lights[1].power *= 1.5
        base = dict(ds.uploads)
        sess.edit(SceneEdit(lights=lights))
        frame = sess.wait(7)
        assert ds.uploads == {**base, "lights": base["lights"] + 1} and not frame.cut
        assert sess.scene.lights[1].power == lights[1].power
        edited.lights = lights
        # a material's colour: the materials only
        edited2 = scenes.moving_box(W, H, frames=1)
        edited2.meshes[1].transforms = np.asarray(moved)[None]
        edited2.lights[1].color = (0.2, 0.4, 1.0)
        edited2.lights[1].power = lights[1].power
        edited2.materials[1].albedo = (0.1, 0.8, 0.1)
        base = dict(ds.uploads)
        sess.edit(SceneEdit(scene=edited2))
        frame = sess.wait(8)
        assert ds.uploads == {**base, "materials": base["materials"] + 1} and not frame.cut
        assert frame.rgba[..., 1].max() > frame.rgba[..., 0].max() * 0.5
        # another topology: uploaded, and the history dropped
        edited3 = scenes.moving_box(W, H, frames=1)
        edited3.meshes[1].transforms = np.asarray(moved)[None]
        edited3.lights[1].color = (0.2, 0.4, 1.0)
        edited3.lights[1].power = lights[1].power
        edited3.materials[1].albedo = (0.1, 0.8, 0.1)
        edited3.meshes[1].vertices = edited3.meshes[1].vertices * 0.5
        sess.edit(SceneEdit(scene=edited3))
        frame = sess.wait(9)
        assert frame.cut and frame.history == 1.0
        assert sess.stats.edits == {"kept": 4, "reset": 1}
    finally:
        assert sess.stop()


def test_the_worker_stops_cleanly_mid_render():
    sess = session(samples=10_000)
    step(sess, orbit_view(0), perspective(0.5), 2)
    t0 = time.perf_counter()
    assert sess.stop(timeout=30.0)
    assert not sess.running and time.perf_counter() - t0 < 30.0
    n = sess.stats.frames
    time.sleep(0.3)
    assert sess.stats.frames == n


def test_pixel_size_scales_the_render():
    assert scaled_size(960, 540, 2) == (480, 270)
    assert scaled_size(961, 541, 1) == (961, 541)
    assert scaled_size(3, 3, 8) == (1, 1)


def test_no_device_that_builds_is_the_header_message_without_a_traceback(monkeypatch, capfd):
    """Without an OpenCL device that builds the kernels the session stops with the error (shown in the viewport's
    header), naming what to install; the console gets no traceback, as for F12."""
    import restircl_blender.viewport_session as vs
    from restircl import DeviceError

    def no_device(*_args, **_kwargs):
        raise DeviceError("no OpenCL device can build kernels; install a driver")

    monkeypatch.setattr(vs, "Renderer", no_device)
    capfd.readouterr()
    sess = session()
    sess.set_view(view_camera(orbit_view(0.0), perspective(0.6), W, H))
    assert sess.wait(1) is None
    assert sess.error == "DeviceError: no OpenCL device can build kernels; install a driver"
    assert sess.stop()
    assert "Traceback" not in "".join(capfd.readouterr())
