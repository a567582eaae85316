"""Render Properties > Motion Blur read for restircl: the shutter's open and close times around the frame
(Position: Start, Center or End; Shutter in frames), the times within it whose motion a still exports, and what is
not blurred (warnings).

A still exports its motion at STEPS + 1 (or more, below) evenly spaced times over the shutter (Blender's subframes),
so that motion
that bends within a frame (Bezier keys easing in and out, Blender's default) is followed within the shutter, and
the renderer interpolates between those (scene/interpolation.py). The export knows whole frames only: the times
reach it as stand-in frame numbers, `frame + k` for the k-th step from the rendered frame, which `subframe` turns
back into Blender's (frame, subframe).

Objects that deform within the shutter have their vertices read at Cycles' deformation motion steps (`deform_steps`:
2^Steps + 1 evenly spaced times from the shutter's opening to its closing, Object > Motion Blur), which the renderer
interpolates linearly, as Cycles does (scene/deformation.py); the shutter's parts are as many as the most steps ask
for, so that every step is one of the exported times."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

from .export.mesh import GEOMETRY_TYPES, may_deform

STEPS = 8  # the shutter's parts between the exported times (at least)
MAX_DEFORM_STEPS = 129  # Cycles' most motion steps of an object


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
    step = (b - a) / max(STEPS, _deform_parts(scene))
    lo, hi = math.floor(a / step + 1e-9), math.ceil(b / step - 1e-9)
    return StillMotion([frame + k for k in range(lo, hi + 1)], step)


def deform_steps(ob, parent=None) -> int:
    """How many times over the shutter Cycles reads the deformation of object `ob` (an instance of `parent`'s):
    2^Steps + 1 (Object > Motion Blur > Steps, `cycles.motion_steps`, at least 1, the larger of the object's and
    the instancer's), at most MAX_DEFORM_STEPS; 0 where Motion Blur or its Deformation is off on either."""
    owners = [o.original if getattr(o, "original", None) is not None else o
              for o in ([ob] if parent is None or parent == ob else [ob, parent])]
    settings = [c for c in (getattr(o, "cycles", None) for o in owners) if c is not None]
    if not all(c.use_motion_blur and c.use_deform_motion for c in settings):
        return 0
    steps = max([1, *(int(c.motion_steps) for c in settings)])
    return min(2 ** steps + 1, MAX_DEFORM_STEPS)


def _deform_parts(scene) -> int:
    """The shutter's parts that put every deformation step of the scene's objects that may deform on an exported
    time (a power of two)."""
    return max([0, *(deform_steps(ob) - 1 for ob in scene.objects if ob.type in GEOMETRY_TYPES and may_deform(ob))])


def shutter_middle(scene, frame: int) -> int:
    """The stand-in frame number (StillMotion) of the middle of the shutter of a still at `frame`, where Cycles reads
    what it does not blur (the shutter's Position moves it off the frame)."""
    numbers = still_motion(scene, frame).frames
    return (numbers[0] + numbers[-1]) // 2


def deform_frames(scene, frame: int) -> Callable[[object], list[int]]:
    """The stand-in frame numbers (StillMotion) at which a still at `frame` reads an object's deformation: its
    `deform_steps` evenly spaced from the shutter's opening to its closing; for an object whose deformation is not
    blurred, the shutter's middle alone (its geometry there, as Cycles reads it)."""
    numbers = still_motion(scene, frame).frames
    lo, parts = numbers[0], numbers[-1] - numbers[0]

    def frames(ob, parent=None) -> list[int]:
        n = deform_steps(ob, parent) if parts else 0
        return sorted({lo + round(i * parts / (n - 1)) for i in range(n)}) if n > 1 else [lo + parts // 2]

    return frames


def animation_deform_times(scene, frames: list[int], frame: int, steps: int) -> list[float]:
    """The Blender times (frames) at which an animation frame `frame` reads the deformation of an object with
    `steps` deformation steps (deform_steps): each over the shutter of every exported frame (`frames`) up to
    `frame` (the warm-up frames before it render at their own shutters' times) and of the exported frame after it
    (the Vector pass's next time), evenly spaced from its opening to its closing; none without motion blur or
    without steps."""
    a, b = shutter(scene)
    if a == b or steps < 2:
        return []
    read = [f for f in frames if f <= frame] + [f for f in frames if f > frame][:1]
    return sorted({round(f + a + (b - a) * i / (steps - 1), 9) for f in read for i in range(steps)})


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
    frame index `current` of the exported restircl.Scene `scene` (the shutter's middle, `shutter_middle`, where
    Cycles reads them) over the whole shutter."""
    still = {ob.name for ob in objects
             if getattr(getattr(ob, "cycles", None), "use_motion_blur", True) is False}
    for mesh in scene.meshes:
        if mesh.name in still and mesh.transforms.shape[0] > 1:
            mesh.transforms = mesh.transforms[min(current, mesh.transforms.shape[0] - 1)]


def warn_unblurred(scene, animation: bool, deforming: list[str], warn: Callable[[str], None], objects=()) -> None:
    """What the shutter does not blur: objects that deform within it whose deformation steps were not read
    (`deforming`: the export's deforming objects less those it read the steps of, Export.deform_handled; animation
    frames read theirs after the export: export/frame_deformation.py), a rolling shutter, and in animation frames
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
