"""Deformation within a still's shutter (Blender's armatures, shape keys, animated modifiers): a mesh may carry its
object-space vertices at a few times (Mesh.deform at Mesh.deform_times, scene frames, the topology fixed), and, if
smooth, its shading normals there (Mesh.deform_normals); those at a time between two of the steps are interpolated
linearly, as Cycles interpolates its deformation motion steps (normals renormalised where they are used); before
the first and after the last they are held. The mesh's transform moves the deformed vertices as it moves the others
(scene/interpolation.py)."""

from __future__ import annotations

import numpy as np

from .errors import SceneError


def at_time(still: np.ndarray, steps: np.ndarray | None, times: np.ndarray | None, frame: float) -> np.ndarray:
    """Per-vertex (or per-corner) values at `frame`: `still` without deformation steps, else `steps` (S, ...) at
    `times` (S,) interpolated."""
    if steps is None or times is None:
        return still
    t = np.asarray(times, np.float64)
    f = float(frame)
    if f <= t[0]:
        return steps[0]
    if f >= t[-1]:
        return steps[-1]
    hi = int(np.searchsorted(t, f, side="right"))
    lo = hi - 1
    u = (f - t[lo]) / (t[hi] - t[lo])
    if u == 0.0:
        return steps[lo]
    return (1.0 - u) * steps[lo] + u * steps[hi]


def check_deform(deform: np.ndarray | None, times: np.ndarray | None, normals: np.ndarray | None,
                 counts: tuple[int, int], label: str) -> None:
    """Raise SceneError unless `deform` is None with `times` and `normals`, or (S, V, 3) finite at S >= 2 increasing
    times, with `normals` None or (S, T, 3, 3) finite; `counts`: the mesh's (V, T)."""
    if deform is None and normals is not None:
        raise SceneError(f"{label}: deform_normals without deform")
    if deform is None and times is None:
        return
    if deform is None or times is None:
        raise SceneError(f"{label}: deform and deform_times go together")
    s = len(times)
    vertex_count, triangle_count = counts
    if np.shape(deform) != (s, vertex_count, 3) or s < 2:
        raise SceneError(f"{label}: deform must have shape (S, {vertex_count}, 3) with S >= 2 steps, one per "
                         f"deform_time ({s}), got shape {np.shape(deform)}")
    if normals is not None and (np.shape(normals) != (s, triangle_count, 3, 3) or not np.all(np.isfinite(normals))):
        raise SceneError(f"{label}: deform_normals must be finite, shape ({s}, {triangle_count}, 3, 3), got shape "
                         f"{np.shape(normals)}")
    if not np.all(np.isfinite(deform)) or not np.all(np.isfinite(times)):
        raise SceneError(f"{label}: deform or deform_times contain NaN or Inf")
    if np.any(np.diff(times) <= 0):
        raise SceneError(f"{label}: deform_times must increase, got {list(np.asarray(times).tolist())}")
