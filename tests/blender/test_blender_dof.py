"""Depth of field against Cycles: a thin lens with Blender's camera settings (F-stop, focus object or distance,
blades, rotation and ratio), read by the add-on's camera export and rendered by F12 with the reference method.
The negative controls misread one setting in ours (the focus, the ratio, the blades' rotation) and must fail the
same bound.

relMSE as in test_blender_cycles.py; figures measured when written are in docs/blender.md ("Depth of field")."""

from __future__ import annotations

import math

import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402
from restircl.eval.blender_scenes import comparison_scene  # noqa: E402

from .test_blender_support import assert_agrees, cycles_and_ours, ensure_registered, needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

BOUND = 0.01


def dof_scene(blades: int = 0, rotation: float = 0.0, ratio: float = 1.0):
    """The comparison scene (floor, wall, box; a point light and a spot) seen through a wide aperture focused on
    the box: the floor before it and the wall behind it blur by several pixels at 64x48."""
    sc = comparison_scene("mixed", 64, 48)
    dof = sc.camera.data.dof
    dof.use_dof = True
    dof.focus_object = bpy.data.objects["Box"]
    dof.aperture_fstop = 0.02  # 30 mm / (2 x 0.02): a 75 cm radius
    dof.aperture_blades = blades
    dof.aperture_rotation = rotation
    dof.aperture_ratio = ratio
    return sc


def bokeh_scene(blades: int = 0, rotation: float = 0.0, ratio: float = 1.0, ortho: bool = False):
    """A glowing square 6 m away, the camera focused at 2 m: its image (15 pixels across) spreads over the
    aperture's image (20 pixels across), so that the blades, their rotation and the ratio show in the outline. The
    square is about as large as the blur so that most lens rays of a pixel in it find it, or noise would swamp
    the comparison."""
    sc = scenes.new_scene(64, 48)
    scenes.quad("Spark", 1.0, 1.0, scenes.emission_material("Spark", (1.0, 0.9, 0.7), 5.0),
                rotation=(math.pi / 2, 0, 0))
    cam = scenes.camera((0, -6, 0), (0, 0, 0), lens=50.0)
    if ortho:  # a 2.4 m wide view; the aperture is 1 / (2 F-stop), in metres
        cam.data.type, cam.data.ortho_scale = "ORTHO", 2.4
    dof = cam.data.dof
    dof.use_dof = True
    dof.focus_distance = 2.0
    dof.aperture_fstop = 2.0 if ortho else 0.074  # 25 cm, or 50 mm / (2 x 0.074): 34 cm
    dof.aperture_blades = blades
    dof.aperture_rotation = rotation
    dof.aperture_ratio = ratio
    return sc


def test_export_reads_the_lens():
    from restircl_blender import export as ex

    ensure_registered()
    sc = dof_scene(blades=6, rotation=0.4, ratio=1.5)
    cam = ex.export_scene(bpy.context.evaluated_depsgraph_get(), None, frame_set=sc.frame_set).scene.camera
    # the camera at (0, -5.5, 3.5) looks at (0, 0.5, 0.3); the box's origin is at (0.3, 0.2, 0.4)
    axis = (0.0, 6.0, -3.2)
    norm = math.sqrt(sum(a * a for a in axis))
    depth = ((0.3 - 0.0) * axis[0] + (0.2 + 5.5) * axis[1] + (0.4 - 3.5) * axis[2]) / norm
    assert cam.focus_distance == pytest.approx(depth, rel=1e-5)
    assert cam.aperture_radius == pytest.approx(0.030 / (2 * 0.02))
    assert (cam.aperture_blades, cam.aperture_rotation, cam.aperture_ratio) == (6, pytest.approx(0.4), 1.5)
    sc.camera.data.dof.use_dof = False
    cam = ex.export_scene(bpy.context.evaluated_depsgraph_get(), None, frame_set=sc.frame_set).scene.camera
    assert cam.aperture_radius == 0.0 and not cam.has_dof


def test_dof_agrees_with_cycles(tmp_path, record_property):
    assert_agrees(tmp_path, dof_scene(), 512, 256, "dof focused on the box", record_property, shared=("dof",))


def test_export_follows_a_focus_pull():
    """The focus object walks away from the camera over frames 1..3: the export holds its depth at each frame."""
    from restircl_blender import export as ex

    sc = dof_scene()
    box = bpy.data.objects["Box"]
    sc.frame_start, sc.frame_end = 1, 3
    for f, y in ((1, -2.0), (2, 0.2), (3, 2.0)):
        box.location.y = y
        box.keyframe_insert("location", frame=f)
    sc.frame_set(2)
    cam = ex.export_scene(bpy.context.evaluated_depsgraph_get(), [1, 2, 3], frame_set=sc.frame_set).scene.camera
    m = sc.camera.matrix_world
    axis = -m.col[2].xyz.normalized()
    want = []
    for f in (1, 2, 3):
        sc.frame_set(f)
        want.append((box.matrix_world.translation - m.translation).dot(axis))
    assert cam.focus_per_frame == pytest.approx(want, rel=1e-5)
    assert want[0] < want[1] < want[2]


# The default suite keeps a polygon turned (5 blades, 0.6) and a stretched disc (ratio 2): the two lenses the
# negative controls below misread, whose Cycles images they share (the round lens is test_dof_agrees_with_cycles'
# and the orthographic one a turned pentagon); the round disc, the unturned hexagon and the squeezed disc (ratio
# 0.5) read the same settings again and run behind `slow` (docs/measurements/benchmarks.md, "Test suite time").
BOKEH = [
    pytest.param(0, 0.0, 1.0, marks=pytest.mark.slow),
    (5, 0.6, 1.0),
    pytest.param(6, 0.0, 1.0, marks=pytest.mark.slow),
    (0, 0.0, 2.0),
    pytest.param(0, 0.0, 0.5, marks=pytest.mark.slow),
]


@pytest.mark.parametrize(("blades", "rotation", "ratio"), BOKEH)
def test_bokeh_agrees_with_cycles(tmp_path, blades, rotation, ratio, record_property):
    """Perspective cameras; the orthographic one below."""
    assert_agrees(tmp_path, bokeh_scene(blades, rotation, ratio), 4096, 2048,
                  f"bokeh blades {blades} rotation {rotation} ratio {ratio}", record_property,
                  shared=("bokeh", blades, rotation, ratio))


def test_orthographic_bokeh_agrees_with_cycles(tmp_path, record_property):
    assert_agrees(tmp_path, bokeh_scene(5, 0.3, ortho=True), 4096, 2048, "orthographic bokeh", record_property)


# the control's scene (built with the arguments, as an agreement test above renders it: its Cycles image is shared)
WRONG = {
    "focus": (dof_scene, (), lambda p: p.update(focus_distance=p["focus_distance"] * 1.6)),
    "ratio": (bokeh_scene, (0, 0.0, 2.0), lambda p: p.update(aperture_ratio=1.0 / p["aperture_ratio"])),
    "rotation": (bokeh_scene, (5, 0.6, 1.0),
                 lambda p: p.update(aperture_rotation=p["aperture_rotation"] + math.pi / 5)),
}


@pytest.mark.parametrize("wrong", sorted(WRONG))
def test_dof_negative_control(tmp_path, monkeypatch, wrong):
    """Ours with the lens misread (focused 1.6 times farther, the ratio inverted, the polygon turned by half a
    corner) must fail the bound that the right reading passes: the scene tells these apart."""
    from restircl_blender.export import camera as camera_export

    real = camera_export.lens_params
    make, scene_args, spoil = WRONG[wrong]

    def misread(cam_obj, warn):
        p = real(cam_obj, warn)
        if bpy.context.scene.render.engine == "RESTIRCL":
            spoil(p)
        return p

    monkeypatch.setattr(camera_export, "lens_params", misread)
    samples = (4096, 2048) if make is bokeh_scene else (512, 256)  # as the agreement tests render them
    shared = ("bokeh", *scene_args) if make is bokeh_scene else ("dof",)
    err, _ = cycles_and_ours(tmp_path, make(*scene_args), *samples, f"dof, {wrong} misread", shared)
    assert err > BOUND, f"a misread {wrong} passed: relMSE {100 * err:.3f} %"
