"""The lights camera rays see (opencl/lights/camera_visible.h): which of a scene's lights Cycles would show to the
camera, and the table the primary pass reads (their light indices and per-light motion rows).

Which lights is decided here, once, on the host: those visible to the camera whose type says they have a shape
(SceneLightType.has_shape, lights/<type>.py: not a delta). The device tests exactly the lights of the table and has
no rule of its own: what a ray sees of one is its type's hit, evaluation and radiance (opencl/lights/lights.h)."""

from __future__ import annotations

import warnings

import numpy as np

from ..scene.scene import Scene
from .registry import type_of

# A camera ray tests every light of the table: past this many, the rest are not seen (and a warning says so).
CAMERA_LIGHTS_MAX = 256
ROWS = 7  # rows per light of the table (CAMERA_LIGHT_ROWS in opencl/codes.h)


def camera_light_indices(scene: Scene) -> list[int]:
    """Indices (into scene.lights, the first device light records) of the lights camera rays test."""
    seen = [i for i, lt in enumerate(scene.lights)
            if getattr(lt, "visible_camera", True) and type_of(lt).has_shape(lt)]
    if len(seen) > CAMERA_LIGHTS_MAX:
        warnings.warn(f"{len(seen)} lights are visible to the camera; only the first {CAMERA_LIGHTS_MAX} are seen "
                      "(turn Ray Visibility > Camera off for the others)", stacklevel=2)
        seen = seen[:CAMERA_LIGHTS_MAX]
    return seen


def camera_light_table(scene: Scene, indices: list[int], source: np.ndarray, frame: int, prev_frame: int,
                       next_frame: int) -> np.ndarray:
    """(1 + 7 len(indices), 4) float32: the count, then per light its device record index (the record whose
    `source`, DeviceLights.source, is its scene index) and the rows of M_prev M_cur^-1 and M_next M_cur^-1 (its own
    motion between the frames)."""
    record_of = {int(s): k for k, s in enumerate(np.asarray(source)) if 0 <= s < len(scene.lights)}
    table = np.zeros((1 + ROWS * len(indices), 4), np.float32)
    ints = table.view(np.int32)
    ints[0, 0] = len(indices)
    for k, i in enumerate(indices):
        tr = scene.lights[i].transforms
        cur = Scene.at(tr, frame)
        inv = np.linalg.inv(cur)
        base = 1 + ROWS * k
        ints[base, 0] = record_of[i]
        table[base + 1:base + 4] = (Scene.at(tr, prev_frame) @ inv)[:3]
        table[base + 4:base + 7] = (Scene.at(tr, next_frame) @ inv)[:3]
    return table
