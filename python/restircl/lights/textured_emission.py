"""The light an emissive triangle sheds when its emission colour is an image (a screen, a lit sign, a glTF
emissive map). Its power is the mean of the image over the triangle's UV footprint, times Emission Strength,
computed here on the host: the radiance of the triangle's light record, by which the light array and tree pick it.
Its light at a point is the image at that point (point_emission_data: the record flagged LIGHT_FLAG_TEXTURED and
pointed at a block in the light buffer, read by opencl/lights/textured_emission.h), so next-event estimation is
unbiased where the image varies within a triangle, and the BSDF rays that meet the triangle (direct/,
path/emitters.h) evaluate the same point the same way, which keeps their MIS weights consistent. What the camera
sees directly is the image itself (textures/material.h). An emission that is another node graph keeps the white
bound (Material.radiance) and the upload's warning (upload/textures.py warn_textured_emission)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io.image_load import ImageReadError, mip_chain, read_image_file, to_linear_rgba
from ..materials.textures import ImageTexture

SAMPLES = 8  # sub-triangles per side of the grid over each triangle: SAMPLES**2 points, one in each


def sampled_emission(m) -> ImageTexture | None:
    """The material's emission image when the host can average it (an Image Texture on the UV map), else None."""
    node = m.emission
    if isinstance(node, ImageTexture) and node.coords == "uv" and m.emission_strength > 0:
        return node
    return None


def _linear_levels(node: ImageTexture) -> list[np.ndarray] | None:
    """The image's linear RGB mip chain (box-filtered in linear light), bottom row first; None when unreadable
    (the upload warns about it and renders it magenta)."""
    try:
        pixels = read_image_file(node.image) if isinstance(node.image, str | Path) else np.asarray(node.image)
        texels = to_linear_rgba(pixels, node.colorspace if node.colorspace == "sRGB" else "Non-Color")
    except (ImageReadError, OSError):
        return None
    return mip_chain(np.nan_to_num(texels[..., :3], nan=0.0, posinf=0.0, neginf=0.0))


def _wrap(i: np.ndarray, n: int, extension: str) -> tuple[np.ndarray, np.ndarray]:
    if extension == "REPEAT":
        return np.mod(i, n), np.ones(i.shape, bool)
    inside = (i >= 0) & (i < n) if extension == "CLIP" else np.ones(i.shape, bool)
    return np.clip(i, 0, n - 1), inside


def _lookup(level: np.ndarray, st: np.ndarray, node: ImageTexture) -> np.ndarray:
    """Bilinear (or Closest) lookups of (n, 2) image coordinates in one level, as textures/image.h reads them."""
    h, w = level.shape[:2]
    p = st * np.array([w, h]) - (0.5 if node.interpolation != "Closest" else 0.0)
    if node.interpolation == "Closest":
        x, okx = _wrap(np.floor(p[:, 0]).astype(np.int64), w, node.extension)
        y, oky = _wrap(np.floor(p[:, 1]).astype(np.int64), h, node.extension)
        return level[y, x] * (okx & oky)[:, None]
    f = np.floor(p)
    t = p - f
    out = np.zeros((len(st), 3))
    for dx, dy in ((0, 0), (1, 0), (0, 1), (1, 1)):
        x, okx = _wrap(f[:, 0].astype(np.int64) + dx, w, node.extension)
        y, oky = _wrap(f[:, 1].astype(np.int64) + dy, h, node.extension)
        wgt = (t[:, 0] if dx else 1 - t[:, 0]) * (t[:, 1] if dy else 1 - t[:, 1]) * (okx & oky)
        out += level[y, x] * wgt[:, None]
    return out


def _grid() -> np.ndarray:
    """(k, 3) barycentric weights of a regular grid of points inside the triangle (centroids of its sub-triangles
    pointing up), each standing for an equal area."""
    n = SAMPLES
    pts = [((i + 1 / 3) / n, (j + 1 / 3) / n) for i in range(n) for j in range(n - i)]
    pts += [((i + 2 / 3) / n, (j + 2 / 3) / n) for i in range(n) for j in range(n - i - 1)]
    b = np.array(pts)
    return np.column_stack([1 - b[:, 0] - b[:, 1], b[:, 0], b[:, 1]])


def image_mean(node: ImageTexture, uvs: np.ndarray, levels: list[np.ndarray]) -> np.ndarray:
    """(T, 3) mean linear colour of the image over each triangle of (T, 3, 2) corner UVs: a grid of points per
    triangle read at the mip level where the points are about a texel apart, so every texel under it counts."""
    b = _grid()
    st = np.einsum("kc,tcd->tkd", b, uvs)
    if node.mapping is not None:
        m = np.asarray(node.mapping, dtype=np.float64)
        xyz = np.concatenate([st, np.zeros(st.shape[:2] + (1,))], axis=-1)
        st = (xyz @ m[:3, :3].T + m[:3, 3])[..., :2]
    h, w = levels[0].shape[:2]
    d1, d2 = uvs[:, 1] - uvs[:, 0], uvs[:, 2] - uvs[:, 0]
    area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) * w * h  # texels under the triangle
    lvl = np.clip(np.ceil(0.5 * np.log2(np.maximum(area / len(b), 1.0))), 0, len(levels) - 1).astype(np.int64)
    out = np.zeros((len(uvs), 3))
    for k in np.unique(lvl):
        sel = lvl == k
        vals = _lookup(levels[k], st[sel].reshape(-1, 2), node).reshape(int(sel.sum()), len(b), 3)
        out[sel] = vals.mean(axis=1)
    return out


def triangle_radiance(scene, world) -> np.ndarray:
    """(T, 3) emitted radiance of each triangle of `world` (scene.WorldTriangles): its material's constant
    radiance, or the mean of its emission image over the triangle times Emission Strength (see the module)."""
    rad = np.array([m.radiance for m in scene.materials]).reshape(-1, 3) if scene.materials else np.zeros((0, 3))
    le = rad[world.material] if len(rad) else np.zeros((len(world), 3))
    for i, m in enumerate(scene.materials):
        node = sampled_emission(m)
        if node is None or not np.any(world.material == i):
            continue
        levels = _linear_levels(node)
        if levels is None:
            continue
        for obj in np.unique(world.object[world.material == i]):
            mesh = scene.meshes[int(obj)]
            sel = np.nonzero((world.material == i) & (world.object == obj))[0]
            uvs = mesh.uvs[world.prim[sel]] if mesh.uvs is not None else np.zeros((len(sel), 3, 2))
            le[sel] = image_mean(node, np.asarray(uvs, np.float64), levels) * float(m.emission_strength)
    return le


MAX_LIGHT_TEXELS = 1 << 22  # texels of the image level a textured light reads at its points (the finest that fits)
BLOCK = 12  # floats of a textured triangle's block (opencl/lights/textured_emission.h)


def _corner_st(node: ImageTexture, uvs: np.ndarray) -> np.ndarray:
    """(T, 3, 2) image coordinates of the corners: the UVs through the node's Mapping (affine, so the point's is the
    barycentric blend of its corners')."""
    if node.mapping is None:
        return uvs
    m = np.asarray(node.mapping, dtype=np.float64)
    xyz = np.concatenate([uvs, np.zeros(uvs.shape[:2] + (1,))], axis=-1)
    return (xyz @ m[:3, :3].T + m[:3, 3])[..., :2]


def point_emission_data(scene, world, records: np.ndarray, source: np.ndarray, start: int) -> np.ndarray:
    """Flag the records (the (N, 16) float32 lanes, in place) of the emissive triangles whose emission is an image
    (sampled_emission) LIGHT_FLAG_TEXTURED, pointing their a.w at a block, and give the floats that hold their
    blocks and images: the device reads the image at each sampled point (opencl/lights/textured_emission.h). The
    floats go into the light buffer `start` floats after the records. The triangle's mean (its record's radiance)
    still gives its power, by which it is picked."""
    from ..materials.textures import EXTENSIONS, INTERPOLATIONS
    from .record import FLAG_TEXTURED

    n = len(records)
    rows = np.nonzero(source < 0)[0]
    tri = -1 - source[rows]
    chunks: list[np.ndarray] = []
    pos = start
    for i, m in enumerate(scene.materials):
        node = sampled_emission(m)
        mine = rows[world.material[tri] == i] if node is not None else rows[:0]
        levels = _linear_levels(node) if len(mine) else None
        if levels is None:
            continue
        level = next((lv for lv in levels if lv.shape[0] * lv.shape[1] <= MAX_LIGHT_TEXELS), levels[-1])
        h, w = level.shape[:2]
        image_pos = pos
        chunks.append(np.ascontiguousarray(level, np.float32).reshape(-1))
        pos += level.size
        t = -1 - source[mine]
        uvs = np.zeros((len(mine), 3, 2))
        for obj in np.unique(world.object[t]):
            sel = world.object[t] == obj
            mesh = scene.meshes[int(obj)]
            if mesh.uvs is not None:
                uvs[sel] = np.asarray(mesh.uvs, np.float64)[world.prim[t[sel]]]
        blocks = np.zeros((len(mine), BLOCK), np.float32)
        blocks[:, :6] = _corner_st(node, uvs).reshape(-1, 6)
        blocks[:, 6] = float(m.emission_strength)
        block_pos = pos + BLOCK * np.arange(len(mine))
        ints = blocks.view(np.int32)
        ints[:, 7] = image_pos - block_pos
        ints[:, 8], ints[:, 9] = w, h
        ints[:, 10], ints[:, 11] = INTERPOLATIONS.index(node.interpolation), EXTENSIONS.index(node.extension)
        lanes = records.view(np.int32)
        lanes[mine, 7] = (n - mine) * 16 + block_pos
        lanes[mine, 15] |= FLAG_TEXTURED
        chunks.append(blocks.reshape(-1))
        pos += blocks.size
    return np.concatenate(chunks) if chunks else np.zeros(0, np.float32)
