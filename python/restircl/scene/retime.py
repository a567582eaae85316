"""A scene's animation cut into more frames along the same motion: `retime(scene, k)` has frame j at time j/k of the
original frames (frame f of the original is frame f*k), so a renderer that is k times faster per frame can be
compared at equal wall time along the same camera path (a higher frame rate), as a real-time renderer would use it.

Transforms are interpolated per component (scene/interpolation.py): translation linearly, rotation by quaternion
slerp, the remaining stretch (polar decomposition M = R S) linearly; per-frame light powers and world strengths
linearly; camera cuts move to their new frame numbers.
"""

from __future__ import annotations

import copy

import numpy as np

from .interpolation import interpolate_transform
from .scene import Scene


def retime_transforms(transforms: np.ndarray, k: int, frames: int, cuts: tuple[int, ...] = ()) -> np.ndarray:
    """(F, 4, 4) per-frame transforms (the last held beyond F) at k sub-frames per frame: (frames-1)*k+1 of them.
    Before a cut (a frame in `cuts`) the sub-frames hold the previous frame's transform: a cut is no motion."""
    if transforms.shape[0] == 1:
        return transforms
    n = (frames - 1) * k + 1
    out = np.empty((n, 4, 4), transforms.dtype)
    last = transforms.shape[0] - 1
    for j in range(n):
        f, r = divmod(j, k)
        a, b = transforms[min(f, last)], transforms[min(f + 1, last)]
        out[j] = a if r == 0 or f + 1 in cuts else interpolate_transform(a, b, r / k)
    return out


def retime_values(values: np.ndarray, k: int, frames: int) -> np.ndarray:
    """(F,) per-frame values (the last held beyond F), linearly interpolated at k sub-frames per frame."""
    t = np.arange((frames - 1) * k + 1) / k
    return np.interp(t, np.arange(len(values)), values).astype(values.dtype)


def retime(scene: Scene, k: int) -> Scene:
    """A copy of `scene` whose animation has k frames for each of the original's (frame f there is f*k here)."""
    if k < 1:
        raise ValueError(f"retime: k must be at least 1, got {k}")
    out = copy.deepcopy(scene)
    if k == 1:
        return out
    n = scene.frames
    cam = out.camera
    assert cam is not None
    cam.transforms = retime_transforms(cam.transforms, k, n, cam.cuts)
    cam.cuts = tuple(c * k for c in cam.cuts)
    for obj in [*out.meshes, *out.lights]:
        obj.transforms = retime_transforms(obj.transforms, k, n)
    for mesh in out.meshes:
        if mesh.deform_times is not None:
            mesh.deform_times = mesh.deform_times * k
    for lt in out.lights:
        if lt.power_per_frame is not None and len(lt.power_per_frame) > 1:
            lt.power_per_frame = retime_values(lt.power_per_frame, k, n)
    env = out.environment
    if env is not None and env.strength_per_frame is not None and len(env.strength_per_frame) > 1:
        env.strength_per_frame = retime_values(np.asarray(env.strength_per_frame, np.float64), k, n)
    if out.frame_count is not None:
        out.frame_count = (int(out.frame_count) - 1) * k + 1
    return out.validate()
