"""The motion of a deforming mesh between two times as one affine map: the reprojection and the Vector pass move
each object's surface points by one 3x4 row block per object (M_other M_cur^-1, camera/primary.cl), so a mesh whose
vertices deform (Mesh.deform, animation frames at their shutters' times) gets the affine map of world space that
carries its vertices at the current time nearest (least squares) to where they are at the other time. Exact where
the deformation is affine (a shape key that slides, stretches or turns the mesh as a whole); elsewhere the motion
vectors are its best affine part, and TAA's clip box rejects the history that the rest leaves behind."""

from __future__ import annotations

import numpy as np

from ..scene.interpolation import transform_at
from ..scene.mesh import Mesh


def world_vertices(mesh: Mesh, frame: float) -> np.ndarray:
    """(V, 3) the mesh's vertices in world space at `frame` (deformed, then transformed)."""
    m = transform_at(mesh.transforms, frame)
    return mesh.vertices_at(frame) @ m[:3, :3].T + m[:3, 3]


def deform_motion(mesh: Mesh, frame: float, other: float) -> np.ndarray:
    """(3, 4) rows of the affine map taking the mesh's world-space vertices at `frame` nearest to theirs at `other`
    (the minimum-norm fit where the vertices span less than 3D, e.g. a flat mesh: exact on its plane)."""
    cur, to = world_vertices(mesh, frame), world_vertices(mesh, other)
    if frame == other or np.array_equal(cur, to):
        return np.eye(4)[:3]
    at, to_at = cur.mean(axis=0), to.mean(axis=0)  # about the centroids: a flat mesh's fit stays well conditioned
    x, *_ = np.linalg.lstsq(cur - at, to - to_at, rcond=None)
    rows = np.empty((3, 4))
    rows[:, :3] = x.T
    rows[:, 3] = to_at - x.T @ at
    return rows
