"""Render Properties > Motion Blur read for restircl: the shutter's open and close times around the frame
(Position: Start, Center or End; Shutter in frames), the times within it whose motion a still exports, and what is
not blurred (warnings).

A still exports its motion at STEPS + 1 evenly spaced times over the shutter (Blender's subframes), so that motion
that bends within a frame (Bezier keys easing in and out, Blender's default) is followed within the shutter, and
the renderer interpolates between those (scene/interpolation.py). The export knows whole frames only: the times
reach it as stand-in frame numbers, `frame + k` for the k-th step from the rendered frame, which `subframe` turns
back into Blender's (frame, subframe)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

STEPS = 8  # the shutter's parts between the exported times


class StillMotion(NamedTuple):
    """The stand-in frame numbers a still exports, and the time (frames) between two of them."""

    frames: list[int]
    step: float


def shutter(scene) -> tuple[float, float]:
    """(open, close) in frames from the rendered frame; (0, 0): no motion blur."""
    r = scene.render
    if not r.use_motion_blur or r.motion_blur_shutter <= 0.0:
        return (0.0, 0.0)
    s = float(r.motion_blur_shutter)
    return {"START": (0.0, s), "END": (-s, 0.0)}.get(r.motion_blur_position, (-0.5 * s, 0.5 * s))


def still_motion(scene, frame: int) -> StillMotion:
    """What a still (F12) at `frame` exports: the shutter's times, or the frame alone."""
    a, b = shutter(scene)
    if a == b:
        return StillMotion([frame], 1.0)
    step = (b - a) / STEPS
    lo, hi = math.floor(a / step + 1e-9), math.ceil(b / step - 1e-9)
    return StillMotion([frame + k for k in range(lo, hi + 1)], step)


def subframe(number: int, frame: int, step: float) -> tuple[int, float]:
    """Blender's (frame, subframe) of stand-in frame `number` of a still at `frame` (StillMotion)."""
    t = frame + (number - frame) * step
    whole = math.floor(t + 1e-9)
    return whole, max(0.0, t - whole)


def scene_shutter(scene, step: float) -> tuple[float, float]:
    """The shutter in the exported scene's frames (Camera.shutter), `step` frames apart."""
    a, b = shutter(scene)
    return a / step, b / step


def hold_unblurred(scene, objects, current: int) -> None:
    """Objects whose own Motion Blur is off (Object > Motion Blur, `cycles.use_motion_blur`) stay where they are at
    the rendered frame (frame index `current` of the exported restircl.Scene `scene`) over the whole shutter."""
    still = {ob.name for ob in objects
             if getattr(getattr(ob, "cycles", None), "use_motion_blur", True) is False}
    for mesh in scene.meshes:
        if mesh.name in still and mesh.transforms.shape[0] > 1:
            mesh.transforms = mesh.transforms[min(current, mesh.transforms.shape[0] - 1)]


def warn_unblurred(scene, animation: bool, deforming: list[str], warn: Callable[[str], None], objects=()) -> None:
    """What the shutter does not blur: objects that deform within it, a rolling shutter, and in animation frames
    (one time of the shutter per frame, accumulated by TAA: render/shutter.py) the objects whose own Motion Blur is
    off, which move with the rest (`objects`: the scene's)."""
    if shutter(scene) == (0.0, 0.0):
        return
    if deforming:
        warn(f"object(s) {', '.join(repr(n) for n in deforming[:5])} deform within the shutter: their deformation "
             "is not blurred (their geometry at the frame moves with their transform only)")
    held = [ob.name for ob in objects if getattr(getattr(ob, "cycles", None), "use_motion_blur", True) is False]
    if animation and held:
        warn(f"object(s) {', '.join(repr(n) for n in held[:5])} have their Motion Blur off: animation frames blur "
             "them with the rest (still renders keep them sharp)")
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and getattr(cycles, "rolling_shutter_type", "NONE") != "NONE":
        warn("rolling shutter is not rendered: the whole image is exposed at once")
