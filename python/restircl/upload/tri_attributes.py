"""Per-triangle surface attributes for the primary hit (TriAttr, ObjectInfo in opencl/types.h; read by
opencl/textures/point.h): world-space corner normals of smooth shading (Mesh.normals), the UV map (Mesh.uvs) with a
tangent from its derivatives, object-space corners (Object and Generated coordinates), and the texture-to-world
area ratios from which the ray cone picks a mip level. In BVH leaf order, as make_tris lays out the triangles."""

from __future__ import annotations

import numpy as np

from ..core import layouts as L
from ..lights.light_groups import group_of
from ..scene.mesh import Mesh
from ..scene.scene import Scene, WorldTriangles

#: ObjectInfo flags (OBJECT_* in opencl/codes.h): its triangles have TriAttr records; its TriAttr normals are
#: Mesh.normals (shade smooth); it has a UV map; it is a holdout (Mesh.holdout, camera/primary.cl); the camera does
#: not see it (Mesh.camera_visible, camera/hidden.h)
OBJECT_ATTRIBUTES, OBJECT_NORMALS, OBJECT_UVS, OBJECT_HOLDOUT, OBJECT_CAMERA_HIDDEN = 1, 2, 4, 8, 16
LOD_FLOOR = -60.0  # 0.5 log2 of a vanishing area ratio: the finest level, never -inf


def needs_attributes(scene: Scene, textured: bool) -> bool:
    return textured or any(m.normals is not None for m in scene.meshes)


def texture_space(mesh: Mesh) -> tuple[np.ndarray, np.ndarray]:
    """(centre, scale) of Blender's automatic texture space: generated = (p - centre) * scale + 0.5, scale =
    1 / (max - min); a flat axis gets Blender's half size 1 (generated 0.5 there), a tiny one at least 1e-5."""
    if len(mesh.vertices) == 0:
        return np.zeros(3), np.ones(3)
    lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    half = 0.5 * (hi - lo)
    half = np.where(half == 0, 1.0, np.maximum(half, 1e-5))
    return 0.5 * (lo + hi), 0.5 / half


def object_infos(scene: Scene, attributes: bool) -> np.ndarray:
    info = np.zeros(max(len(scene.meshes), 1), L.OBJECT_INFO)
    for k, mesh in enumerate(scene.meshes):
        mid, scale = texture_space(mesh)
        flags = 0
        if attributes:
            flags = OBJECT_ATTRIBUTES | (OBJECT_NORMALS if mesh.normals is not None else 0)
            flags |= OBJECT_UVS if mesh.uvs is not None else 0
        flags |= OBJECT_HOLDOUT if mesh.holdout else 0
        flags |= 0 if mesh.camera_visible else OBJECT_CAMERA_HIDDEN
        info["gen_mid"][k, :3] = mid
        info["gen_mid"][k, 3] = L.int_bits(np.array([flags]))[0]
        info["gen_scale"][k, :3] = scale
        info["gen_scale"][k, 3] = L.int_bits(np.array([group_of(scene, mesh.lightgroup)]))[0]  # film/light_groups.h
    return info


def _half_log_ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        r = 0.5 * np.log2(num / den)
    return np.where(np.isfinite(r), r, LOD_FLOOR)


def _area3(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=-1)


def tri_attributes(scene: Scene, world: WorldTriangles, order: np.ndarray, frame: int) -> np.ndarray:
    """TriAttr records of the world triangles in BVH leaf order (`order`, BVH.order) at `frame`."""
    out = np.zeros(max(len(order), 1), L.TRI_ATTR)
    obj = world.object[order]
    prim = world.prim[order]
    p0, p1, p2 = world.v0[order], world.v1[order], world.v2[order]
    e1, e2 = p1 - p0, p2 - p0
    face = np.cross(e1, e2)
    world_area = 0.5 * np.linalg.norm(face, axis=1)
    face_n = face / np.maximum(2.0 * world_area, 1e-300)[:, None]
    for k, mesh in enumerate(scene.meshes):
        sel = np.nonzero(obj == k)[0]
        if len(sel) == 0:
            continue
        t = prim[sel]
        corners = mesh.vertices_at(frame)[mesh.triangles[t]]  # (n, 3, 3) object space
        if mesh.normals is not None:
            inv = np.linalg.inv(Scene.at(mesh.transforms, frame)[:3, :3])
            n = mesh.normals_at(frame)[t] @ inv  # the inverse transpose, on row vectors
            length = np.linalg.norm(n, axis=2, keepdims=True)
            n = np.where(length > 0, n / np.where(length > 0, length, 1.0), 0.0)
        else:
            n = np.repeat(face_n[sel][:, None], 3, axis=1)
        for c, name in enumerate(("n0", "n1", "n2")):
            out[name][sel, :3] = n[:, c]
        uv = np.asarray(mesh.uvs, np.float64)[t] if mesh.uvs is not None else np.zeros((len(t), 3, 2))
        out["u"][sel, :3] = uv[:, :, 0]
        out["v"][sel, :3] = uv[:, :, 1]
        d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
        det = d1[:, 0] * d2[:, 1] - d2[:, 0] * d1[:, 1]
        out["u"][sel, 3] = _half_log_ratio(0.5 * np.abs(det), world_area[sel])
        ok = det != 0
        inv_det = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)[:, None]
        tangent = (e1[sel] * d2[:, 1:2] - e2[sel] * d1[:, 1:2]) * inv_det
        bitangent = (e2[sel] * d1[:, 0:1] - e1[sel] * d2[:, 0:1]) * inv_det
        sign = np.where(np.einsum("ij,ij->i", np.cross(face_n[sel], tangent), bitangent) < 0, -1.0, 1.0)
        out["tangent"][sel, :3] = tangent
        out["v"][sel, 3] = sign
        out["o0"][sel, :3] = corners[:, 0]
        out["oe1"][sel, :3] = corners[:, 1] - corners[:, 0]
        out["oe2"][sel, :3] = corners[:, 2] - corners[:, 0]
        out["o0"][sel, 3] = _half_log_ratio(_area3(corners[:, 0], corners[:, 1], corners[:, 2]), world_area[sel])
        mid, scale = texture_space(mesh)
        g = (corners - mid) * scale + 0.5
        out["oe1"][sel, 3] = _half_log_ratio(_area3(g[:, 0], g[:, 1], g[:, 2]), world_area[sel])
    return out
