"""Depth of field in the Rendered viewport, by Cycles' viewport rules: through the camera (Camera View) the view
has that camera's thin lens (aperture from the camera's own focal length and F-stop, its focus object or distance,
blades, rotation, ratio; the 3D view's local camera when it has one); any other view is a pinhole. The session
behind the viewport (headless: bpy in background draws nothing) converges to the still render of the same lens,
and the pinhole session (negative control) fails the same bound."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from .test_blender_support import ensure_registered, needs_renderer  # noqa: E402

ensure_registered()

from restircl import Renderer, Settings, scenes  # noqa: E402
from restircl.eval import blender_scenes as bscenes  # noqa: E402
from restircl.eval.metrics import rel_mse  # noqa: E402
from restircl_blender.viewport_session import ViewportSession, view_camera  # noqa: E402

from .test_viewport_session import H, W, orbit_view, perspective  # noqa: E402

pytestmark = pytest.mark.blender

LENS = {"aperture_radius": 0.25, "focus_distance": 2.5}  # focused in front of the box: everything blurs
BOUND = 0.01  # relMSE of the viewport's 32 averaged frames against a 512-sample still of the same lens


def converged_session(thin_lens: dict | None, samples: int) -> np.ndarray:
    """The session's frame after `samples` frames of a still view (rows from the top, RGB)."""
    sess = ViewportSession(scenes.moving_box(W, H, frames=1), Settings(), samples=samples).start()
    try:
        sess.set_view(view_camera(orbit_view(0), perspective(0.5), W, H, thin_lens=thin_lens))
        frame = sess.wait(samples)
        assert sess.error is None, sess.error
        assert frame is not None and frame.samples == samples
        return frame.rgba[::-1, :, :3]
    finally:
        sess.stop()


@needs_renderer
def test_the_session_converges_to_the_lens_of_its_view():
    sc = scenes.moving_box(W, H, frames=1)
    sc.camera = view_camera(orbit_view(0), perspective(0.5), W, H, thin_lens=LENS)
    assert sc.camera.aperture_radius == 0.25 and sc.camera.focus_distance == 2.5
    reference = Renderer(sc, Settings()).render_still(samples=512).color[..., :3]
    with_lens = rel_mse(converged_session(LENS, 32), reference)
    pinhole = rel_mse(converged_session(None, 32), reference)
    print(f"viewport with the lens {with_lens:.5f}, pinhole {pinhole:.5f} (bound {BOUND})")
    assert with_lens < BOUND
    assert pinhole > BOUND  # negative control: the view without the lens


def camera_scene(use_dof: bool = True):
    sc = bscenes.new_scene(32, 24, engine="RESTIRCL")
    bscenes.box("Box", (0.8, 0.8, 0.8), bscenes.diffuse_material("Red", (0.8, 0.2, 0.1)), location=(0.3, 0.2, 0.4))
    cam = bscenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    cam.data.dof.use_dof = use_dof
    cam.data.dof.aperture_fstop = 0.7
    cam.data.dof.focus_distance = 3.0
    cam.data.dof.aperture_blades = 5
    cam.data.dof.aperture_rotation = 0.3
    cam.data.dof.aperture_ratio = 1.25
    return sc, cam


def view_context(cam, perspective_mode: str, local=None):
    """A 3D view's context looking through `cam` (view matrix = its inverse) with a zoomed camera view's window."""
    from mathutils import Matrix

    view = np.linalg.inv(np.asarray(cam.matrix_world, np.float64))
    window = np.array([[3.0, 0, 0, 0], [0, 4.0, 0, 0], [0, 0, -1.002, -0.2], [0, 0, -1.0, 0]])  # not the lens's
    rv3d = SimpleNamespace(view_matrix=Matrix(view.tolist()), window_matrix=Matrix(window.tolist()),
                           is_perspective=True, view_perspective=perspective_mode)
    space = SimpleNamespace(clip_end=100.0, camera=local, use_local_camera=local is not None)
    return SimpleNamespace(region=SimpleNamespace(width=32, height=24), region_data=rv3d, space_data=space)


def test_camera_view_has_the_cameras_lens_and_other_views_none():
    from restircl_blender.viewport import region_camera

    sc, cam = camera_scene()
    dg = bpy.context.evaluated_depsgraph_get()
    through = region_camera(view_context(cam, "CAMERA"), 1, dg)
    assert through.aperture_radius == pytest.approx(0.028 / (2 * 0.7))  # the camera's 28 mm, not the view's zoom
    assert through.focus_distance == pytest.approx(3.0)
    assert (through.aperture_blades, through.aperture_ratio) == (5, 1.25)
    assert through.aperture_rotation == pytest.approx(0.3)
    assert through.lens == pytest.approx(18.0 * 3.0)  # the view's own projection is kept
    # the focus object: the distance along the camera's axis to its origin
    cam.data.dof.focus_object = bpy.data.objects["Box"]
    dg = bpy.context.evaluated_depsgraph_get()
    axis = np.array([0.0, 5.5, -1.9]) / math.hypot(5.5, 1.9)
    depth = float(np.dot(axis, np.array([0.3, 5.2, -2.1])))
    assert region_camera(view_context(cam, "CAMERA"), 1, dg).focus_distance == pytest.approx(depth, rel=1e-5)
    for mode in ("PERSP", "ORTHO"):  # the 3D view's own lens: a pinhole, as Cycles'
        assert region_camera(view_context(cam, mode), 1, dg).aperture_radius == 0.0
    assert region_camera(view_context(cam, "CAMERA"), 1).aperture_radius == 0.0  # no depsgraph: no lens read
    cam.data.dof.use_dof = False
    dg = bpy.context.evaluated_depsgraph_get()
    assert region_camera(view_context(cam, "CAMERA"), 1, dg).aperture_radius == 0.0


def test_a_local_camera_gives_its_own_lens():
    from restircl_blender.viewport import region_camera

    sc, cam = camera_scene(use_dof=False)
    local = bscenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=50.0, name="Local", make_active=False)
    assert sc.camera == cam
    local.data.dof.use_dof = True
    local.data.dof.aperture_fstop = 2.0
    dg = bpy.context.evaluated_depsgraph_get()
    assert region_camera(view_context(cam, "CAMERA", local=local), 1, dg).aperture_radius == pytest.approx(
        0.050 / 4.0)
    assert region_camera(view_context(cam, "CAMERA"), 1, dg).aperture_radius == 0.0  # the scene's: no dof
