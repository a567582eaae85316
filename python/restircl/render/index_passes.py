"""Cycles' Object Index and Material Index passes (IndexOB / IndexMA): the pass index of the object and of the
material that the pixel's camera ray hit (Mesh.pass_index, Material.pass_index), 0 where it hit nothing or a light.
Read from a G-buffer (the object id in albedo.w, lights/linking.py's low bits; the material id in gnormal.w), as
Cycles writes them from one sample: a still's come from its last frame."""

from __future__ import annotations

import numpy as np

from ..core import layouts as L
from ..lights.linking import OBJECT_BITS


def index_images(g: np.ndarray, scene) -> tuple[np.ndarray, np.ndarray]:
    """(H, W) float32 object and material pass indices of a read-back G-buffer of `scene`."""
    hit = L.float_bits_to_int(g["normal"][..., 3]) >= 0
    obj = L.float_bits_to_int(g["albedo"][..., 3]) & ((1 << OBJECT_BITS) - 1)
    mat = L.float_bits_to_int(g["gnormal"][..., 3])
    obj_index = np.array([m.pass_index for m in scene.meshes] or [0], np.float32)
    mat_index = np.array([m.pass_index for m in scene.materials] or [0], np.float32)
    ob = np.where(hit, obj_index[np.clip(obj, 0, len(obj_index) - 1)], 0.0).astype(np.float32)
    ma = np.where(hit, mat_index[np.clip(mat, 0, len(mat_index) - 1)], 0.0).astype(np.float32)
    return ob, ma
