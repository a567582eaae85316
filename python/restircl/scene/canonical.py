"""A scene's content in one order: each mesh's triangles sorted by what they are, not by where they stand in the
arrays.

Blender hands the add-on a mesh's loop triangles in an order that changes from one process to the next (the same
triangles, listed and started at other corners), so two exports of one .blend differ as arrays while they render
the same picture. What is cached under a digest of a scene (converged references, eval/report/reference.py) must
find it again in the next process: the digest is taken of this form, and the reference is rendered from it.

The form: each triangle starts at its corner of lexicographically least position (a rotation keeps its winding),
the triangles are sorted by their corner positions, then material, UVs, normals and attributes, and the vertices
are the distinct corner positions, sorted. Meshes, materials and lights keep their order (Blender lists them by
name). A triangle's index within its mesh changes, which no image depends on.

Blender's corner normals are not bit-stable either: they are sums over a vertex's faces in the order of the process
(the UV spheres of eval/scenes/user_scene.py: 7 % of their normal components differ between two exports, by 1-3
float32 ulps, up to 1.2e-7). `key_scene` rounds them onto a grid of NORMAL_GRID steps per unit for what a key is
taken of. No rounding is free of edges (a value beside a step's edge can land on either side), so two exports of
that scene share a key with probability about 1 - sum(|difference|) x NORMAL_GRID, over 99 % there; a coarser grid
would miss more edits of the normals.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .mesh import Mesh
from .scene import Scene


def _corner_arrays(mesh: Mesh) -> list[tuple[str | None, np.ndarray]]:
    """The mesh's per-corner arrays ((T, 3, k)), with the field (None: an attribute) each lives in."""
    out: list[tuple[str | None, np.ndarray]] = []
    for what in ("uvs", "normals"):
        a = getattr(mesh, what)
        if a is not None:
            out.append((what, np.asarray(a, np.float64)))
    for a in (mesh.attributes or {}).values():
        out.append((None, np.asarray(a, np.float64)))
    return out


def canonical_mesh(mesh: Mesh) -> Mesh:
    """`mesh` with its triangles and vertices in the order of the module's docstring."""
    t = np.asarray(mesh.triangles, np.int64)
    n = len(t)
    if n == 0:
        return dataclasses.replace(mesh)
    corners = mesh.vertices[t]  # (T, 3, 3)
    flat = corners.reshape(-1, 3)
    rank = np.empty(len(flat), np.int64)
    rank[np.lexsort(flat.T[::-1])] = np.arange(len(flat))
    first = rank.reshape(n, 3).argmin(axis=1)
    roll = (first[:, None] + np.arange(3)[None, :]) % 3  # a rotation: the winding stays
    corners = np.take_along_axis(corners, roll[:, :, None], axis=1)
    per_corner = [(what, np.take_along_axis(a, roll[:, :, None], axis=1)) for what, a in _corner_arrays(mesh)]
    keys = np.concatenate([corners.reshape(n, -1), np.asarray(mesh.material_ids, np.float64)[:, None],
                           *(a.reshape(n, -1) for _, a in per_corner)], axis=1)
    order = np.lexsort(keys.T[::-1])
    corners = corners[order]
    vertices, index = np.unique(corners.reshape(-1, 3), axis=0, return_inverse=True)
    changed: dict = {"vertices": vertices, "triangles": index.reshape(n, 3),
                     "material_ids": np.asarray(mesh.material_ids)[order]}
    attributes = dict(mesh.attributes or {})
    names = iter(list(attributes))
    for what, a in per_corner:
        if what is None:
            attributes[next(names)] = a[order]
        else:
            changed[what] = a[order]
    if mesh.attributes is not None:
        changed["attributes"] = attributes
    return dataclasses.replace(mesh, **changed)


def canonical_scene(scene: Scene) -> Scene:
    """A copy of `scene` whose meshes are in the order of the module's docstring (the other parts are shared)."""
    return dataclasses.replace(scene, meshes=[canonical_mesh(m) for m in scene.meshes])


#: steps per unit of the grid that key_scene rounds shading normals onto (1/64: about 0.9 degrees)
NORMAL_GRID = 64.0


def key_scene(scene: Scene) -> Scene:
    """The canonical form with its corner normals rounded onto the grid of NORMAL_GRID (-0 made +0): what a cache
    key is taken of (its file, and the probe render of eval/report/reference.py), never what a reference renders."""
    canon = canonical_scene(scene)
    meshes = [m if m.normals is None else
              dataclasses.replace(m, normals=np.round(np.asarray(m.normals) * NORMAL_GRID) / NORMAL_GRID + 0.0)
              for m in canon.meshes]
    return dataclasses.replace(canon, meshes=meshes)
