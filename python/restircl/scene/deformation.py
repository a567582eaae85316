"""Deformation within a still's shutter (Blender's armatures, shape keys, animated modifiers): a mesh may carry its
object-space vertices at a few times (Mesh.deform at Mesh.deform_times, scene frames, the topology fixed), and its
vertices at a time between two of those are interpolated linearly, as Cycles interpolates its deformation motion
steps; before the first and after the last they are held. The mesh's transform moves the deformed vertices as it
moves the others (scene/interpolation.py)."""

from __future__ import annotations

import numpy as np

from .errors import SceneError


def vertices_at(vertices: np.ndarray, deform: np.ndarray | None, times: np.ndarray | None,
                frame: float) -> np.ndarray:
    """The (V, 3) object-space vertices at `frame`: `vertices` without deformation steps, else `deform` (S, V, 3)
    at `times` (S,) interpolated."""
    if deform is None or times is None:
        return vertices
    t = np.asarray(times, np.float64)
    f = float(frame)
    if f <= t[0]:
        return deform[0]
    if f >= t[-1]:
        return deform[-1]
    hi = int(np.searchsorted(t, f, side="right"))
    lo = hi - 1
    u = (f - t[lo]) / (t[hi] - t[lo])
    if u == 0.0:
        return deform[lo]
    return (1.0 - u) * deform[lo] + u * deform[hi]


def check_deform(deform: np.ndarray | None, times: np.ndarray | None, vertex_count: int, label: str) -> None:
    """Raise SceneError unless `deform` is None with `times`, or (S, V, 3) finite at S >= 2 increasing times."""
    if deform is None and times is None:
        return
    if deform is None or times is None:
        raise SceneError(f"{label}: deform and deform_times go together")
    s = len(times)
    if np.shape(deform) != (s, vertex_count, 3) or s < 2:
        raise SceneError(f"{label}: deform must have shape (S, {vertex_count}, 3) with S >= 2 steps, one per "
                         f"deform_time ({s}), got shape {np.shape(deform)}")
    if not np.all(np.isfinite(deform)) or not np.all(np.isfinite(times)):
        raise SceneError(f"{label}: deform or deform_times contain NaN or Inf")
    if np.any(np.diff(times) <= 0):
        raise SceneError(f"{label}: deform_times must increase, got {list(np.asarray(times).tolist())}")
