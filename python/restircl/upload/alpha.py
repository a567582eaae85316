"""The coverage of transparent surfaces (materials/alpha.py) where every ray can read it: appended to the Tri array
(opencl/surface/alpha.h), so that shadow rays, camera rays and bounce rays need no buffer beyond the BVH's nodes and
triangles.

The triangle's e1.w (int bits; the original triangle index the host keeps, which no kernel reads) holds -1 for an
opaque triangle, else the float4 index of its record in the tail. The tail, in float4 units after the Tri
records (3 float4 each, packets included):
- per transparent material, ALPHA_MATERIAL float4s: (constant alpha, invert 0/1, has an image 0/1, a smooth thin
  wall 0/1); (int bits: first float4 of its texels, width, height, interpolation | extension << 4); the Mapping
  node's rows u' = (m00, m01, m03) . (u, v, 1) and v' = (m10, m11, m13) . (u, v, 1); a smooth thin wall's record
  (upload/thin_wall_shadow.py: shadow rays pass it), zeros for others; a thin wall that is not otherwise
  transparent has a record here too, of coverage 1;
- per triangle of such a material, ALPHA_TRIANGLE float4s: (u0, u1, u2, int bits: its material's record) and
  (v0, v1, v2, unused);
- each image's scalar texels (alpha or grey, linear, bottom row first), four to a float4.
"""

from __future__ import annotations

import numpy as np

from ..core import layouts as L
from ..io.image_load import read_image_file, to_linear_rgba
from ..materials.alpha import AlphaSource, alpha_source, is_transparent
from ..materials.material import Material
from ..materials.textures import EXTENSIONS, INTERPOLATIONS
from ..scene.scene import Scene
from .thin_wall_shadow import THIN_RECORD, thin_wall_record

ALPHA_MATERIAL = 4 + THIN_RECORD  # float4s per material record
ALPHA_TRIANGLE = 2  # float4s per triangle record
GREY = np.array([0.2126, 0.7152, 0.0722])  # Blender's colour -> value conversion (textures/nodes.h tex_gray)


def scene_is_transparent(scene: Scene) -> bool:
    return any(is_transparent(m) for m in scene.materials)


def _has_record(m: Material) -> bool:
    """Whether rays read a record of m: a coverage below 1 or a thin wall that shadow rays pass."""
    return is_transparent(m) or thin_wall_record(m) is not None


def scene_has_records(scene: Scene) -> bool:
    """Whether some material of the scene has a record (rays pass it: the transparent shadow loop)."""
    return any(_has_record(m) for m in scene.materials)


def _scalar_texels(source: AlphaSource) -> np.ndarray:
    """(H, W) float32 coverage texels of the source's image, bottom row first; an unreadable image is opaque."""
    img = source.image
    assert img is not None
    try:
        pixels = read_image_file(img.image) if isinstance(img.image, str) else np.asarray(img.image)
        rgba = to_linear_rgba(pixels, img.colorspace if img.colorspace == "sRGB" else "Non-Color")
    except Exception:  # noqa: BLE001 - the texture packer warns about the same image; here it is opaque
        return np.ones((1, 1), np.float32)
    rgba = np.where(np.isfinite(rgba), rgba, 0.0)
    values = rgba[..., 3] if source.channel == "alpha" else rgba[..., :3] @ GREY
    return np.ascontiguousarray(values, dtype=np.float32)


def _mapping_rows(source: AlphaSource) -> tuple[np.ndarray, np.ndarray]:
    m = np.eye(4) if source.image is None or source.image.mapping is None else np.asarray(source.image.mapping,
                                                                                              np.float64)
    return np.array([m[0, 0], m[0, 1], m[0, 3], 0.0]), np.array([m[1, 0], m[1, 1], m[1, 3], 0.0])


def transparency_tail(scene: Scene, material: np.ndarray, uvs: np.ndarray, base: int) -> tuple[np.ndarray, np.ndarray]:
    """(e1.w int32 per triangle, the tail as (n, 4) float32) for triangles of materials `material` (leaf order) with
    corner UVs `uvs` (n, 3, 2), the tail starting at float4 index `base` (3 x the Tri records)."""
    records: list[np.ndarray] = []
    texel_blocks: list[np.ndarray] = []
    mat_at: dict[int, int] = {}
    n_mat = sum(1 for m in scene.materials if _has_record(m))
    texel_base = base + n_mat * ALPHA_MATERIAL + int(np.isin(material, [
        k for k, m in enumerate(scene.materials) if _has_record(m)]).sum()) * ALPHA_TRIANGLE
    texel_at = texel_base
    for k, m in enumerate(scene.materials):
        if not _has_record(m):
            continue
        src = alpha_source(m.alpha)
        rec = np.zeros((ALPHA_MATERIAL, 4), np.float32)
        thin = thin_wall_record(m)
        rec[0] = (src.constant, float(src.invert), float(src.image is not None), float(thin is not None))
        if thin is not None:
            rec[4:] = thin
        info = np.zeros(4, np.int32)
        if src.image is not None:
            tex = _scalar_texels(src)
            h, w = tex.shape
            flat = np.zeros(-(-tex.size // 4) * 4, np.float32)
            flat[:tex.size] = tex.reshape(-1)
            texel_blocks.append(flat.reshape(-1, 4))
            info[:] = (texel_at, w, h, INTERPOLATIONS.index(src.image.interpolation)
                       | (EXTENSIONS.index(src.image.extension) << 4))
            texel_at += len(flat) // 4
        rec[1] = L.int_bits(info)
        rec[2], rec[3] = _mapping_rows(src)
        mat_at[k] = base + len(records) * ALPHA_MATERIAL
        records.append(rec)
    e1w = np.full(len(material), -1, np.int32)
    tri_recs = np.zeros((0, 4), np.float32)
    sel = np.nonzero(np.isin(material, list(mat_at)))[0]
    if len(sel):
        tri_recs = np.zeros((len(sel), ALPHA_TRIANGLE, 4), np.float32)
        tri_recs[:, 0, :3] = uvs[sel, :, 0]
        tri_recs[:, 0, 3] = L.int_bits(np.array([mat_at[int(k)] for k in material[sel]], np.int32))
        tri_recs[:, 1, :3] = uvs[sel, :, 1]
        e1w[sel] = base + len(records) * ALPHA_MATERIAL + ALPHA_TRIANGLE * np.arange(len(sel), dtype=np.int32)
        tri_recs = tri_recs.reshape(-1, 4)
    parts = [*(r for r in records), tri_recs, *texel_blocks]
    tail = np.concatenate(parts) if parts else np.zeros((0, 4), np.float32)
    assert base + len(tail) == texel_at
    return e1w, tail.astype(np.float32)


def world_uvs(scene: Scene, obj: np.ndarray, prim: np.ndarray) -> np.ndarray:
    """(n, 3, 2) corner UVs of world triangles (object index, triangle index within its mesh); 0 without a UV map."""
    out = np.zeros((len(obj), 3, 2), np.float64)
    for k, mesh in enumerate(scene.meshes):
        sel = np.nonzero(obj == k)[0]
        if len(sel) and mesh.uvs is not None:
            out[sel] = np.asarray(mesh.uvs, np.float64)[prim[sel]]
    return out


def with_transparency(scene: Scene, tris: np.ndarray, world, order: np.ndarray) -> np.ndarray:
    """The Tri array to upload (make_tris' records first, then any packets): every triangle's e1.w set as the
    module says, and the tail appended when some material is transparent. A scene without one gets e1.w = -1
    everywhere and no tail, so a build that has the transparency code (a general build) reads every triangle as
    opaque."""
    out = tris.copy()
    n = len(order)
    if not scene_has_records(scene):
        out["e1"][:n, 3] = L.int_bits(np.full(n, -1, np.int32))
        return out
    obj, prim = world.object[order], world.prim[order]
    e1w, tail = transparency_tail(scene, np.asarray(world.material)[order], world_uvs(scene, obj, prim), 3 * len(out))
    out["e1"][:n, 3] = L.int_bits(e1w)
    pad = np.zeros((-len(tail) % 3, 4), np.float32)
    return np.concatenate([out, np.concatenate([tail, pad]).reshape(-1).view(L.TRI)])
