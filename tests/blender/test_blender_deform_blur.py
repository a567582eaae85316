"""Deformation motion blur against Cycles: F12 with Render Properties > Motion Blur on, of a glowing bar whose shape
key stretches it (and, in one case, that moves as well), and of a smooth sheet under a sun whose waves travel
(its shading normals follow the deformation), rendered with the reference method. Which objects have
their deformation read, and at which times (Cycles' rule: 2^Steps + 1 steps over the shutter, Object > Motion Blur),
is tested on the export alone. The negative controls render ours with the deformation ignored (the bar as it is at
the frame, as before deformation blur), or the sheet's normals held at the frame: each must fail the bound that
the right one passes.

relMSE as in test_blender_cycles.py; figures measured when written are in docs/blender.md ("Motion blur")."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_motion_blur import fcurves, keyframes  # noqa: E402
from .test_blender_support import assert_agrees, cycles_and_ours, ensure_registered, needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender]

BOUND = 0.01
STRETCH = 1.5  # m the shape key moves the bar's right end at full value
WIDEN = 1.2  # m it moves its top and bottom edges apart each


def deform_scene(position: str = "CENTER", moving: bool = False, eased: bool = False, steps: int = 1):
    """Frame 2 of 1..3: a glowing bar 2 m x 0.4 m facing the camera, whose shape key 'Stretch' (keyed 0 at frame 1,
    1 at frame 3, linear unless eased) moves its right end 1.5 m to the right and its top and bottom edges 1.2 m
    apart each, so that within a shutter of 0.5 frames its end moves 0.375 m and its long edges 0.3 m; `moving`
    also slides the whole bar up 0.4 m a frame."""
    ensure_registered()
    sc = scenes.new_scene(64, 48)
    sc.frame_start, sc.frame_end = 1, 3
    glow = scenes.emission_material("Glow", (1.0, 0.8, 0.5), 3.0)
    scenes.camera((0, -5, 0), (0, 0, 0), lens=30.0)
    bar = scenes.quad("Bar", 2.0, 0.4, glow, rotation=(math.pi / 2, 0, 0))
    bar.shape_key_add(name="Basis")
    key = bar.shape_key_add(name="Stretch")
    for i in (1, 2):  # the quad's corners at +x
        key.data[i].co.x += STRETCH
    for i, sign in ((0, -1), (1, -1), (2, 1), (3, 1)):  # local y: up in the world
        key.data[i].co.y += sign * WIDEN
    block = bar.data.shape_keys.key_blocks["Stretch"]
    for frame, value in ((1, 0.0), (3, 1.0)):
        block.value = value
        block.keyframe_insert("value", frame=frame)
    if not eased:
        for fc in fcurves(bar.data.shape_keys.animation_data.action):
            for kp in fc.keyframe_points:
                kp.interpolation = "LINEAR"
            fc.update()
    if moving:
        keyframes(bar, "location", {f: (0.0, 0.0, 0.4 * (f - 2)) for f in (1, 2, 3)}, eased=False)
    bar.cycles.motion_steps = steps
    sc.frame_set(2)
    sc.render.use_motion_blur, sc.render.motion_blur_shutter, sc.render.motion_blur_position = True, 0.5, position
    return sc


def export_still(sc, frame: int):
    """The export of a still at `frame`, as the engine's (its shutter's times and deformation steps)."""
    from restircl_blender import export, motion_blur

    motion = motion_blur.still_motion(sc, frame)

    def frame_set(number: int) -> None:
        whole, sub = motion_blur.subframe(number, frame, motion.step)
        sc.frame_set(whole, subframe=sub)

    return export.export_scene(bpy.context.evaluated_depsgraph_get(), motion.frames, frame_set=frame_set,
                               deform=motion_blur.deform_frames(sc, frame))


@needs_renderer
@pytest.mark.parametrize(("position", "moving", "eased", "steps"), [
    ("CENTER", False, False, 1), ("START", True, False, 1), ("END", False, True, 2)])
def test_deformation_blur_agrees_with_cycles(tmp_path, position, moving, eased, steps, record_property):
    assert_agrees(tmp_path, deform_scene(position, moving, eased, steps), 512, 256,
                  f"deformation blur {position}{' moving' if moving else ''}{' eased' if eased else ''} "
                  f"steps {steps}", record_property, shared=(position, moving, eased, steps))


@needs_renderer
def test_deformation_off_agrees_with_cycles(tmp_path, record_property):
    """Deformation off with the shutter at Start: Cycles renders the bar as it is at the shutter's middle."""
    sc = deform_scene("START")
    bpy.data.objects["Bar"].cycles.use_deform_motion = False
    assert_agrees(tmp_path, sc, 512, 256, "deformation off, START", record_property)


@needs_renderer
def test_ignored_deformation_is_a_negative_control(tmp_path, monkeypatch):
    """Ours with no deformation steps read: the bar at the frame, sharp."""
    from restircl_blender import motion_blur

    monkeypatch.setattr(motion_blur, "deform_frames", lambda scene, frame: lambda ob, parent=None: [])
    err, _ = cycles_and_ours(tmp_path, deform_scene(), 512, 256, "deformation blur ignored",
                             ("CENTER", False, False, 1))
    assert err > BOUND, f"ignored deformation passed: relMSE {100 * err:.3f} %"


def wave_scene():
    """Frame 2 of 1..3, shutter 1 frame from Start: a smooth 4 m sheet of 48 x 48 quads seen from above, lit by a
    sun 57 degrees from the vertical, with waves 0.12 m high along x whose phase moves a quarter turn over frames
    1..3 (two shape keys, sine and cosine, keyed linearly). The normals tilt by up to 25 degrees and turn with the
    phase; held at the shutter's opening, the shading is that of the opening."""
    ensure_registered()
    sc = scenes.new_scene(64, 48)
    sc.frame_start, sc.frame_end = 1, 3
    grey = scenes.diffuse_material("Grey", (0.8, 0.8, 0.8))
    scenes.camera((0, 0, 5), (0, 0, 0), lens=35.0)
    n = 48
    u = np.linspace(-2.0, 2.0, n + 1)
    row = n + 1
    sheet = scenes.mesh_object("Sheet", [(x, y, 0.0) for y in u for x in u],
                               [(j * row + i, j * row + i + 1, (j + 1) * row + i + 1, (j + 1) * row + i)
                                for j in range(n) for i in range(n)], grey)
    for f in sheet.data.polygons:
        f.use_smooth = True
    sheet.shape_key_add(name="Basis")
    for name, wave in (("Sin", math.sin), ("Cos", math.cos)):
        key = sheet.shape_key_add(name=name)
        for i, v in enumerate(sheet.data.vertices):
            key.data[i].co.z = 0.12 * wave(4.0 * v.co.x)
    blocks = sheet.data.shape_keys.key_blocks
    for frame, (a, b) in ((1, (1.0, 0.0)), (3, (0.0, 1.0))):
        blocks["Sin"].value, blocks["Cos"].value = a, b
        blocks["Sin"].keyframe_insert("value", frame=frame)
        blocks["Cos"].keyframe_insert("value", frame=frame)
    for fc in fcurves(sheet.data.shape_keys.animation_data.action):
        for kp in fc.keyframe_points:
            kp.interpolation = "LINEAR"
        fc.update()
    scenes.light("SUN", "Sun", (0, 0, 5), rotation=(0.0, 1.0, 0.0), energy=3.0)
    sc.frame_set(2)
    sc.render.use_motion_blur, sc.render.motion_blur_shutter, sc.render.motion_blur_position = True, 1.0, "START"
    return sc


@needs_renderer
def test_smooth_normals_follow_the_deformation(tmp_path, record_property):
    assert_agrees(tmp_path, wave_scene(), 256, 128, "deformation blur, smooth travelling waves", record_property,
                  shared=("waves",))


@needs_renderer
def test_normals_held_at_the_frame_are_a_negative_control(tmp_path, monkeypatch):
    import restircl

    monkeypatch.setattr(restircl.Mesh, "normals_at",
                        lambda self, frame: None if self.normals is None else np.asarray(self.normals, np.float64))
    err, _ = cycles_and_ours(tmp_path, wave_scene(), 256, 128, "deformation blur, normals at the frame", ("waves",))
    assert err > BOUND, f"normals held at the frame passed: relMSE {100 * err:.3f} %"


class _Cycles:
    def __init__(self, blur: bool = True, deform: bool = True, steps: int = 1) -> None:
        self.use_motion_blur, self.use_deform_motion, self.motion_steps = blur, deform, steps


class _Object:
    def __init__(self, **cycles) -> None:
        self.cycles = _Cycles(**cycles)
        self.original = None


@pytest.mark.parametrize(("own", "parent", "expected"), [
    ({}, None, 3), ({"steps": 2}, None, 5), ({"steps": 3}, None, 9), ({"steps": 7}, None, 129),
    ({"steps": 8}, None, 129), ({"steps": 0}, None, 3), ({"deform": False}, None, 0), ({"blur": False}, None, 0),
    ({"steps": 1}, {"steps": 3}, 9), ({"steps": 3}, {"steps": 1}, 9), ({}, {"deform": False}, 0),
    ({}, {"blur": False}, 0)])
def test_deform_steps_follow_cycles_rule(own, parent, expected):
    """Cycles' object_motion_steps and object_use_deform_motion (intern/cycles/blender/util.h): 2^Steps + 1 steps
    (Steps at least 1, the larger of the object's and its instancer's), at most 129, none where Motion Blur or
    Deformation is off on either."""
    from restircl_blender import motion_blur

    ob = _Object(**own)
    assert motion_blur.deform_steps(ob, None if parent is None else _Object(**parent)) == expected


@pytest.mark.parametrize(("position", "steps", "frames"), [
    ("CENTER", 1, [-2, 2, 6]), ("START", 1, [2, 6, 10]), ("END", 1, [-6, -2, 2]), ("CENTER", 2, [-2, 0, 2, 4, 6]),
    ("CENTER", 3, list(range(-2, 7)))])
def test_deformation_is_read_at_cycles_steps(position, steps, frames):
    """The stand-in frames (frame 2, shutter 0.5: 8 parts of 1/16 frame) where the bar's vertices are read, and the
    vertices exported there: the shape key's value is linear in time, 0.25 a frame from 0 at frame 1."""
    from restircl_blender import motion_blur

    sc = deform_scene(position, steps=steps)
    bar = bpy.data.objects["Bar"]
    motion = motion_blur.still_motion(sc, 2)
    assert motion.step == pytest.approx(1 / 16)
    read = motion_blur.deform_frames(sc, 2)
    assert read(bar) == frames
    exp = export_still(sc, 2)
    mesh = exp.scene.meshes[0]
    assert exp.deform_handled == ["Bar"]
    assert mesh.deform_times.tolist() == [motion.frames.index(f) for f in frames]
    times = [2 + (f - 2) / 16 for f in frames]  # Blender frames
    right_end = [1.0 + STRETCH * 0.5 * (t - 1) for t in times]
    assert mesh.deform[:, 1, 0] == pytest.approx(right_end, abs=1e-6)
    assert mesh.deform[:, 0, 0] == pytest.approx([-1.0] * len(frames))
    assert mesh.deform[:, 2, 1] == pytest.approx([0.2 + WIDEN * 0.5 * (t - 1) for t in times], abs=1e-6)
    assert not any("deform" in w for w in exp.warnings)


def test_more_steps_than_the_shutter_has_parts_make_more_parts():
    """Steps 4 (17 deformation steps) on the bar: the shutter is cut into 16 parts, not 8, so that every step is an
    exported time; an object that cannot deform (a plain mesh) asks for none."""
    from restircl_blender import motion_blur

    sc = deform_scene(steps=4)
    motion = motion_blur.still_motion(sc, 2)
    assert motion.step == pytest.approx(1 / 32)
    assert motion.frames == list(range(-6, 11))
    assert motion_blur.deform_frames(sc, 2)(bpy.data.objects["Bar"]) == motion.frames
    plain = scenes.quad("Plain", 1.0)
    plain.cycles.motion_steps = 6
    assert motion_blur.still_motion(sc, 2).step == pytest.approx(1 / 32)


@pytest.mark.parametrize(("position", "value"), [("CENTER", 0.5), ("START", 0.625), ("END", 0.375)])
def test_deformation_off_is_read_at_the_shutters_middle(position, value):
    """Object > Motion Blur > Deformation off: the bar sharp, as it is at the shutter's middle (the shape key's value
    there: 0.25 a frame from 0 at frame 1), as Cycles renders it, and no warning."""
    sc = deform_scene(position)
    bpy.data.objects["Bar"].cycles.use_deform_motion = False
    exp = export_still(sc, 2)
    mesh = exp.scene.meshes[0]
    assert mesh.deform is None
    assert mesh.vertices[1, 0] == pytest.approx(1.0 + STRETCH * value)
    assert exp.deforming == ["Bar"] and exp.deform_handled == ["Bar"]
    assert not any("deform" in w for w in exp.warnings)


def test_changing_topology_is_not_blurred_and_said():
    """A Build modifier that adds faces within the shutter: the vertex count changes, so (as in Cycles) the object's
    deformation is not blurred, with a warning naming it."""

    ensure_registered()
    sc = scenes.new_scene(64, 48)
    scenes.camera((0, -5, 0), (0, 0, 0))
    verts = [(x, 0.0, z) for z in (0.0, 0.5) for x in np.linspace(-1.0, 1.0, 9)]
    faces = [(i, i + 1, i + 10, i + 9) for i in range(8)]
    strip = scenes.mesh_object("Strip", verts, faces, scenes.emission_material("Glow"))
    build = strip.modifiers.new("Build", "BUILD")
    build.frame_start, build.frame_duration = 1, 8
    sc.frame_set(4)
    sc.render.use_motion_blur = True
    sc.render.motion_blur_shutter = 1.0
    exp = export_still(sc, 4)
    assert exp.scene.meshes[0].deform is None
    assert any("'Strip'" in w and "vertex count" in w for w in exp.warnings)
