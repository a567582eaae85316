"""Whether a bake has texels to write: Cycles' bake writes a texel only where a face of the object covers it in the
UV map, so a UV map of zero area on the material's faces (every UV on one point or one line) leaves the image
unwritten, and what Blender then returns (zeros, or a few texels at the point's corner) says nothing reliable. The
map is checked before the bake, on the mesh itself, so that such a bake is reported as failed on every Blender."""

from __future__ import annotations

import numpy as np

# modifiers that may give the evaluated mesh a UV map of some area where the original's has none; the others (
# subdivision, mirror, array, ...) keep a map of zero area at zero area
UV_WRITERS = {"UV_PROJECT", "UV_WARP", "NODES", "DATA_TRANSFER"}
MIN_TEXELS = 1e-3  # UV area, in texels, below which the map has no texel to bake into


def zero_uv_area(ob, mat, size: int) -> str:
    """Why `ob`'s active render UV map leaves a size x size bake of `mat` nothing to write ("" when it covers
    some area, or when the mesh cannot tell: not a mesh, a modifier that writes UVs, no face using `mat`)."""
    mesh = getattr(ob, "data", None)
    if ob.type != "MESH" or mesh is None or any(m.type in UV_WRITERS for m in ob.modifiers):
        return ""
    layer = next((uv for uv in mesh.uv_layers if uv.active_render), None)
    slots = [i for i, s in enumerate(ob.material_slots) if s.material == mat]
    if layer is None or not slots or len(mesh.polygons) == 0:
        return ""
    area = uv_area(mesh, layer, slots, len(ob.material_slots))
    if area is None or area * size * size >= MIN_TEXELS:
        return ""
    return (f"the UV map {layer.name!r} of object {ob.name!r} has zero area on the faces of material {mat.name!r} "
            f"(its UVs lie on a point or a line), so the bake has no texel to write")


def uv_area(mesh, layer, slots: list[int], n_slots: int) -> float | None:
    """The total area, in UV units, of the faces whose material slot is one of `slots` (None: no such face)."""
    n = len(mesh.polygons)
    start, total, index = (np.empty(n, np.int32) for _ in range(3))
    mesh.polygons.foreach_get("loop_start", start)
    mesh.polygons.foreach_get("loop_total", total)
    mesh.polygons.foreach_get("material_index", index)
    faces = np.isin(np.clip(index, 0, max(n_slots - 1, 0)), slots)  # Blender clamps the index to the last slot
    if not faces.any():
        return None
    uv = np.empty(len(mesh.loops) * 2, np.float32)
    layer.data.foreach_get("uv", uv)
    uv = uv.reshape(-1, 2).astype(np.float64)
    start, total = start[faces].astype(np.int64), total[faces].astype(np.int64)
    face = np.repeat(np.arange(len(start)), total)
    corner = np.arange(int(total.sum())) - np.repeat(np.cumsum(total) - total, total)  # 0 .. total-1 per face
    here = uv[start[face] + corner]
    after = uv[start[face] + (corner + 1) % total[face]]
    twice = here[:, 0] * after[:, 1] - after[:, 0] * here[:, 1]  # the shoelace formula, per face
    return float(np.abs(np.bincount(face, weights=twice, minlength=len(start))).sum() / 2.0)
