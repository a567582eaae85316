"""The add-on's viewport glue in background Blender (no GPU: the drawing itself is replaced by a recorder): the
depsgraph updates of a moved object become a transform edit without a re-export, other edits a re-export; and
view_update / view_draw / free drive a session from a 3D view's region_data to finite frames and a status text,
and stop its worker."""

from __future__ import annotations

import time
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from .test_blender_support import ensure_registered, needs_renderer, scenes  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def small_scene():
    sc = scenes.new_scene(32, 24, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("Red", (0.8, 0.2, 0.1)), location=(0.3, 0, 0.4))
    scenes.light("POINT", "Point", (-1.0, -0.5, 1.5), energy=60.0)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    return sc


def edits_after(change) -> list:
    """The SceneEdits that view_update would make of the depsgraph updates `change()` causes."""
    from restircl_blender import viewport

    bpy.context.view_layer.update()
    out = []

    def handler(_scene, depsgraph):
        out.append(viewport.scene_edit(depsgraph, frozenset({"Box", "Floor"})))

    bpy.app.handlers.depsgraph_update_post.append(handler)
    try:
        change()
        bpy.context.view_layer.update()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(handler)
    return [e for e in out if e is not None]


def test_depsgraph_updates_become_scene_edits():
    small_scene()
    box = bpy.data.objects["Box"]
    [moved] = edits_after(lambda: setattr(box.location, "x", box.location.x + 0.2))
    assert set(moved.transforms) == {"Box"} and moved.scene is None  # nothing re-exported
    assert moved.transforms["Box"][0, 3] == pytest.approx(0.5)
    from restircl_blender import export

    before = export.export_scene(bpy.context.evaluated_depsgraph_get(), None).scene.lights[0].power
    [power] = edits_after(lambda: setattr(bpy.data.objects["Point"].data, "energy", 90.0))
    assert power.scene is None and not power.transforms  # the lights alone are read again
    assert power.lights[0].power == pytest.approx(before * 90.0 / 60.0)
    point = bpy.data.objects["Point"]
    [light_moved] = edits_after(lambda: setattr(point.location, "z", point.location.z + 0.5))
    assert light_moved.scene is None and light_moved.lights[0].transforms[0][2, 3] == pytest.approx(2.0)
    bsdf = next(n for n in bpy.data.materials["Red"].node_tree.nodes if n.type == "BSDF_DIFFUSE")
    [colour] = edits_after(lambda: setattr(bsdf.inputs["Color"], "default_value", (0.1, 0.9, 0.1, 1.0)))
    assert colour.scene is not None
    red = next(m for m in colour.scene.materials if m.name == "Red")
    assert red.albedo == pytest.approx((0.1, 0.9, 0.1))


class FakeEngine:
    def __init__(self):
        self.viewport = None
        self.stats: list[str] = []
        self.redraws = 0

    def update_stats(self, _a, b):
        self.stats.append(b)

    def tag_redraw(self):
        self.redraws += 1


def region_context(view: np.ndarray, window: np.ndarray, width: int = 64, height: int = 48):
    from mathutils import Matrix

    rv3d = SimpleNamespace(view_matrix=Matrix(view.tolist()), window_matrix=Matrix(window.tolist()),
                           is_perspective=window[3, 3] == 0.0, view_perspective="PERSP")
    return SimpleNamespace(region=SimpleNamespace(width=width, height=height), region_data=rv3d,
                           space_data=SimpleNamespace(clip_end=100.0))


@needs_renderer
def test_view_update_and_draw_run_a_session(monkeypatch):
    from restircl import look_at
    from restircl_blender import viewport

    sc = small_scene()
    sc.restircl.viewport_samples = 3
    sc.restircl.viewport_pixel_size = 2
    drawn = []
    monkeypatch.setattr(viewport, "draw_frame", lambda engine, scene, vp, frame, w, h: drawn.append(
        (frame.rgba.shape, w, h, bool(np.all(np.isfinite(frame.rgba))))))
    engine = FakeEngine()
    dg = bpy.context.evaluated_depsgraph_get()
    viewport.view_update(engine, None, dg)
    session = engine.viewport.session
    assert session is not None, engine.viewport.message
    window = np.array([[2.0, 0, 0, 0], [0, 2.0 * 64 / 48, 0, 0], [0, 0, -1.002, -0.2], [0, 0, -1.0, 0]])
    ctx = region_context(np.linalg.inv(look_at((0.0, -5.0, 2.5), (0.0, 0.5, 0.6))), window)
    deadline = time.monotonic() + 120
    while (not drawn or session.latest().samples < 3) and time.monotonic() < deadline:
        viewport.view_draw(engine, ctx, dg)
        time.sleep(0.05)
    assert session.error is None, session.error
    viewport.view_draw(engine, ctx, dg)  # the done frame
    assert drawn and drawn[-1] == ((24, 32, 4), 64, 48, True)  # pixel size 2: half the region each way
    assert "sample 3/3" in engine.stats[-1] and "ms/frame" in engine.stats[-1]
    redraws = engine.redraws
    viewport.view_draw(engine, ctx, dg)
    assert engine.redraws == redraws  # done: no more polling
    viewport.free(engine)
    assert engine.viewport is None and not session.running
