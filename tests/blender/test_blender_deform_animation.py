"""Deformation blur in animation frames: a glowing bar that a shape key slides steadily, rendered by the
add-on's animation path (ReSTIR DI + TAA, each frame at one time of its shutter, re-exported each frame as the
geometry deforms) with Render Properties > Motion Blur on, against Cycles' blurred frame. The negative control
renders ours with no deformation steps read (the bar as it is at each whole frame) and must fail the bound that the
blurred frame passes, as must ours with the deformation read but its motion vectors left out (the bar's motion rows
the identity); the times the steps are read at are checked on their own.

Error as in test_blender_motion_blur.py (image_error); figures measured when written are in docs/blender.md
("Motion blur")."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_motion_blur import fcurves, image_error  # noqa: E402
from .test_blender_support import (  # noqa: E402
    ensure_registered,
    needs_renderer,
    read_exr_passes,
    record_engine,
    render_to,
)

pytestmark = [pytest.mark.blender]

FRAME = 10  # rendered after 9 warm-up frames, so that TAA has gathered frames at 10 times of the shutter
UNIT = 0.75  # m the shape key moves the bar per unit of its value
BOUND = 0.05  # as the sliding bar's animation frame (test_blender_motion_blur.py)


def slide_scene():
    """The sliding bar of test_blender_motion_blur.py (a glowing upright bar 0.3 m x 3 m, 0.5 m a frame past the
    camera over frames 1..16, its shutter a whole frame around the frame, its blur about 5 pixels wide at 64x48),
    moved by a shape key that shifts all its vertices, not by its transform: a deformation alone (the key's value
    keyed linearly 0 at frame 1 and 10 at frame 16, each unit 0.75 m)."""
    ensure_registered()
    sc = scenes.new_scene(64, 48)
    sc.frame_start = sc.frame_end = FRAME
    glow = scenes.emission_material("Glow", (1.0, 0.8, 0.5), 3.0)
    scenes.camera((0, -5, 0), (0, 0, 0), lens=30.0)
    bar = scenes.quad("Bar", 0.3, 3.0, glow, location=(-3.0, 0.0, 0.0), rotation=(math.pi / 2, 0, 0))
    bar.shape_key_add(name="Basis")
    key = bar.shape_key_add(name="Slide")
    for point in key.data:
        point.co.x += UNIT
    block = bar.data.shape_keys.key_blocks["Slide"]
    block.slider_max = 10.0
    for frame, value in ((1, 0.0), (16, 10.0)):
        block.value = value
        block.keyframe_insert("value", frame=frame)
    for fc in fcurves(bar.data.shape_keys.animation_data.action):
        for kp in fc.keyframe_points:
            kp.interpolation = "LINEAR"
        fc.update()
    sc.frame_set(FRAME)
    sc.render.use_motion_blur, sc.render.motion_blur_shutter = True, 1.0
    return sc


@pytest.fixture(scope="module")
def cycles_slide(tmp_path_factory) -> np.ndarray:
    """Cycles' motion-blurred frame FRAME (an emitter against black: 256 samples converge it)."""
    path = tmp_path_factory.mktemp("cycles_slide") / "cycles.exr"
    sc = slide_scene()
    scenes.cycles_direct_only(sc, samples=256, seed=1, threads=2)
    render_to(sc, path)
    return read_exr_passes(path)["Combined"]


def animation_frame(tmp_path, monkeypatch) -> tuple[np.ndarray, list[str]]:
    """Frame FRAME rendered by the add-on's animation path, and what it reported."""
    reports, _ = record_engine(monkeypatch)
    sc = slide_scene()
    sc.render.engine = "RESTIRCL"
    sc.restircl.warmup_frames = FRAME - 1
    render_to(sc, tmp_path / "anim_", animation=True)
    return read_exr_passes(tmp_path / f"anim_{FRAME:04d}.exr")["Combined"], reports


@needs_renderer
def test_a_deforming_animation_frame_agrees_with_cycles(tmp_path, monkeypatch, cycles_slide, record_property):
    ours, reports = animation_frame(tmp_path, monkeypatch)
    err = image_error(ours, cycles_slide)
    record_property("error", err)
    print(f"deforming animation frame with motion blur: error {err:.4f} against Cycles")
    assert not [m for m in reports if "blur" in m], reports
    assert err < BOUND, f"error {err:.4f} against Cycles' blurred frame"


@needs_renderer
def test_unblurred_deformation_in_animation_fails_the_bound(tmp_path, monkeypatch, cycles_slide):
    from restircl_blender import motion_blur

    monkeypatch.setattr(motion_blur, "animation_deform_times", lambda *args: [])
    ours, _ = animation_frame(tmp_path, monkeypatch)
    err = image_error(ours, cycles_slide)
    print(f"unblurred deformation in an animation frame: error {err:.4f} against Cycles' blurred frame")
    assert err > BOUND, f"unblurred deformation passed: error {err:.4f}"


@needs_renderer
def test_deformation_without_its_motion_vectors_fails_the_bound(tmp_path, monkeypatch, cycles_slide):
    """The steps read, but the deforming bar's motion rows the identity (its transform's, which does not move):
    TAA's history does not follow the bar, and each frame keeps one time of its shutter."""
    from restircl.upload import device_scene

    monkeypatch.setattr(device_scene, "deform_motion", lambda mesh, frame, other: np.eye(4)[:3])
    ours, _ = animation_frame(tmp_path, monkeypatch)
    err = image_error(ours, cycles_slide)
    print(f"deformation without its motion vectors in an animation frame: error {err:.4f} against Cycles")
    assert err > BOUND, f"deformation without motion vectors passed: error {err:.4f}"


def test_animation_reads_the_deformation_over_each_rendered_frames_shutter():
    """Frame 10 with 2 warm-up frames (8, 9 exported before it, 11 and 12 after), Steps 1 (3 steps): the shutters
    of frames 8, 9 and 10 and of the next, 11 (the Vector pass's), never 12's."""
    from restircl_blender import motion_blur

    sc = slide_scene()
    assert motion_blur.animation_deform_times(sc, [8, 9, 10, 11, 12], 10, 3) == [
        7.5, 8.0, 8.5, 9.0, 9.5, 10.0, 10.5, 11.0, 11.5]
    sc.render.motion_blur_shutter, sc.render.motion_blur_position = 0.5, "START"
    assert motion_blur.animation_deform_times(sc, [9, 10], 10, 5) == [
        9.0, 9.125, 9.25, 9.375, 9.5, 10.0, 10.125, 10.25, 10.375, 10.5]
    assert motion_blur.animation_deform_times(sc, [9, 10, 11], 10, 0) == []
    sc.render.use_motion_blur = False
    assert motion_blur.animation_deform_times(sc, [9, 10, 11], 10, 3) == []
