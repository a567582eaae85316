"""The add-on's viewport glue in background Blender (the drawing itself is replaced by a recorder here; it runs for
real in blender/test_viewport_draw.py): the depsgraph updates of a moved object become a transform edit without a
re-export, a light's or a material's edit a re-read of the lights or the materials alone, other edits a re-export;
a material edit uploads the materials alone (the texels only when an image changed); and view_update / view_draw /
free drive a session from a 3D view's region_data to finite frames and a status text, and stop its worker."""

from __future__ import annotations

import time
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered, needs_renderer  # noqa: E402

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


def on_updates(change, handler) -> None:
    """Make `change()` with `handler(depsgraph)` called for its depsgraph updates, as Blender calls view_update."""
    bpy.context.view_layer.update()

    def post(_scene, depsgraph):
        handler(depsgraph)

    bpy.app.handlers.depsgraph_update_post.append(post)
    try:
        change()
        bpy.context.view_layer.update()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(post)


def edits_after(change) -> list:
    """The SceneEdits that view_update would make of the depsgraph updates `change()` causes."""
    from restircl_blender import export, viewport

    bpy.context.view_layer.update()
    exp = export.export_scene(bpy.context.evaluated_depsgraph_get(), None)
    vp = viewport.Viewport(None, (), viewport.unique_mesh_names(exp.scene), material_reads=exp.material_reads)
    out = []
    on_updates(change, lambda depsgraph: out.append(viewport.scene_edit(depsgraph, vp)))
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
    assert colour.scene is None and colour.lights is None and not colour.transforms  # the materials alone
    assert [m.name for m in colour.materials] == [m.name for m in before_materials()]  # in the export's order
    red = next(m for m in colour.materials if m.name == "Red")
    assert red.albedo == pytest.approx((0.1, 0.9, 0.1))
    # another material on the box (its slot): the meshes' export changes, the scene is exported again
    other = scenes.diffuse_material("Blue", (0.1, 0.1, 0.9))
    [slot] = edits_after(lambda: setattr(box.material_slots[0], "material", other))
    assert slot.scene is not None and "Blue" in [m.name for m in slot.scene.materials]


def before_materials() -> list:
    from restircl_blender import export

    return export.export_scene(bpy.context.evaluated_depsgraph_get(), None).scene.materials


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
    # the header: samples, ms per frame, device
    assert "sample 3/3" in engine.stats[-1] and "ms/frame" in engine.stats[-1]
    assert session.device_label and engine.stats[-1].endswith(f"| {session.device_label}")
    redraws = engine.redraws
    viewport.view_draw(engine, ctx, dg)
    assert engine.redraws == redraws  # done: no more polling
    viewport.free(engine)
    assert engine.viewport is None and not session.running


def object_mask(session, name: str) -> np.ndarray:
    """Pixels of the session's last frame (rows bottom first, as ViewFrame.rgba) that show mesh `name`."""
    from restircl.core.layouts import float_bits_to_int

    r = session.renderer
    g = r.read_gbuffer()
    index = [m.name for m in session.scene.meshes].index(name)
    hit = float_bits_to_int(g["normal"][..., 3]) >= 0
    return (hit & (float_bits_to_int(g["albedo"][..., 3]) == index))[::-1]


@needs_renderer
def test_a_material_edit_uploads_only_the_materials():
    """A Principled base colour and a roughness edit re-read the materials alone and upload their records, not the
    geometry, the lights or the texels, and keep the history; the next frame shows the new colour. An edit of an
    image uploads its texels too."""
    from restircl_blender import viewport

    sc = scenes.new_scene(32, 24, engine="RESTIRCL")
    sc.restircl.viewport_samples = 1  # one frame per edit, then the worker sleeps (the G-buffer is read)
    sc.restircl.viewport_pixel_size = 1
    floor = scenes.principled_material("Floor", (0.8, 0.8, 0.8))
    image = bpy.data.images.new("Paint", 4, 4)
    image.generated_color = (0.2, 0.2, 0.8, 1.0)
    tex = floor.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = image
    coords = floor.node_tree.nodes.new("ShaderNodeTexCoord")  # the quad has no UV map
    floor.node_tree.links.new(coords.outputs["Generated"], tex.inputs["Vector"])
    floor_bsdf = next(n for n in floor.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    floor.node_tree.links.new(tex.outputs["Color"], floor_bsdf.inputs["Base Color"])
    scenes.quad("Floor", 10.0, 10.0, floor)
    paint = scenes.principled_material("Paint", (0.8, 0.05, 0.05))
    scenes.box("Box", (1.2, 1.2, 1.2), paint, location=(0.0, 0.5, 0.6))
    scenes.light("POINT", "Point", (-1.0, -1.5, 2.5), energy=200.0)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    engine = FakeEngine()
    viewport.view_update(engine, None, bpy.context.evaluated_depsgraph_get())
    session = engine.viewport.session
    assert session is not None, engine.viewport.message
    window = np.array([[2.0, 0, 0, 0], [0, 2.0 * 32 / 24, 0, 0], [0, 0, -1.002, -0.2], [0, 0, -1.0, 0]])
    from restircl import look_at

    session.set_view(viewport.view_camera(np.linalg.inv(look_at((0.0, -5.0, 2.5), (0.0, 0.5, 0.6))), window, 32, 24))
    try:
        first = session.wait(1)
        assert session.error is None, session.error
        box, on_floor = object_mask(session, "Box"), object_mask(session, "Floor")
        assert box.sum() > 20 and on_floor.sum() > 20
        red = first.rgba[box][:, :3].mean(0)
        assert red[0] > 4 * red[1], red
        ds = session.renderer.device_scene
        steps = [
            ("base colour", lambda: setattr(next(n for n in paint.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
                                            .inputs["Base Color"], "default_value", (0.05, 0.8, 0.05, 1.0)),
             {"materials": 1}),
            ("roughness", lambda: setattr(floor_bsdf.inputs["Roughness"], "default_value", 0.3), {"materials": 1}),
            ("image", lambda: setattr(image, "generated_color", (0.8, 0.6, 0.1, 1.0)),
             {"materials": 1, "textures": 1}),
        ]
        frames = {}
        for k, (what, change, uploaded) in enumerate(steps):
            before = dict(ds.uploads)
            on_updates(change, lambda depsgraph: viewport.view_update(engine, None, depsgraph))
            frame = session.wait(2 + k)
            assert session.error is None, session.error
            assert frame.index == 2 + k and not frame.cut, what
            assert session.renderer.device_scene is ds, what  # no new renderer
            assert {key: n - before[key] for key, n in ds.uploads.items() if n != before[key]} == uploaded, what
            frames[what] = frame.rgba
        assert session.stats.edits == {"kept": 3}
        green = frames["base colour"][box][:, :3].mean(0)
        assert green[1] > 4 * green[0], green  # the next frame shows the new colour
        blue, orange = frames["roughness"][on_floor][:, :3].mean(0), frames["image"][on_floor][:, :3].mean(0)
        assert blue[2] > 2 * blue[0] and orange[0] > 2 * orange[2], (blue, orange)
    finally:
        viewport.free(engine)
    assert not session.running
