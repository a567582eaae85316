"""The light an emissive triangle sheds when its emission colour is an image (a screen, a lit sign, a glTF
emissive map): the mean of the image over the triangle's UV footprint, times Emission Strength, computed here on
the host. It is the radiance of the triangle's light record, so the light array and tree pick triangles by their
real power, and next-event estimation and the BSDF rays that meet the triangle (direct/, path/emitters.h) see the
same value, which keeps their MIS weights consistent. Within one triangle the light is that mean: what the camera
sees directly stays the image itself (textures/material.h). An emission that is another node graph keeps the
white bound (Material.radiance) and the upload's warning (upload/textures.py warn_textured_emission)."""

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
