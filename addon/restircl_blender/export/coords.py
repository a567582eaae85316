"""The Vector input of a texture node -> restircl texture coordinates ("uv", "generated", "object") and an
optional 4x4 mapping matrix (Blender's Mapping node, Point or Texture type), or None when the vector is something
else (the texture is then baked)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .nodes import find_input, resolve

TEXCOORD_OUTPUTS = {"UV": "uv", "Generated": "generated", "Object": "object"}


@dataclass(frozen=True)
class Coords:
    coords: str
    mapping: np.ndarray | None = None
    uv_map: str = ""  # a UV Map node's named map ("" for the active render map)


def euler_xyz(rx: float, ry: float, rz: float) -> np.ndarray:
    """Blender's XYZ Euler rotation: X first, then Y, then Z."""
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    rot_x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    rot_y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rot_z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rot_z @ rot_y @ rot_x


def mapping_matrix(location, rotation, scale, vector_type: str) -> np.ndarray | None:
    """Point: v' = R (S v) + L. Texture: its inverse. Other types (Vector, Normal) are not positions: None."""
    m = np.eye(4)
    m[:3, :3] = euler_xyz(*rotation) @ np.diag(np.asarray(scale, dtype=np.float64))
    m[:3, 3] = location
    if vector_type == "POINT":
        return m
    if vector_type == "TEXTURE":
        if abs(np.linalg.det(m[:3, :3])) < 1e-12:
            return None
        return np.linalg.inv(m)
    return None


def coords_of(vector_socket, stack: tuple, default: str) -> Coords | None:
    """What feeds a texture node's Vector input; `default` is the node's own coordinates when unlinked."""
    src = resolve(vector_socket, stack)
    if not src.linked:
        return Coords(default)
    if src.kind == "ShaderNodeUVMap":
        return Coords("uv", None, src.node.uv_map or "")
    if src.kind == "ShaderNodeTexCoord":
        kind = TEXCOORD_OUTPUTS.get(src.socket.name)
        if kind is None or (kind == "object" and src.node.object is not None):
            return None
        return Coords(kind)
    if src.kind == "ShaderNodeMapping":
        node = src.node
        parts = [find_input(node, (n,)) for n in ("Location", "Rotation", "Scale")]
        vec = find_input(node, ("Vector",))
        if vec is None or not vec.is_linked or any(p is not None and p.is_linked for p in parts):
            return None
        values = [tuple(p.default_value) if p is not None else d
                  for p, d in zip(parts, ((0, 0, 0), (0, 0, 0), (1, 1, 1)), strict=True)]
        m = mapping_matrix(*values, node.vector_type)
        inner = coords_of(vec, src.stack, default)
        if m is None or inner is None:
            return None
        return Coords(inner.coords, m if inner.mapping is None else m @ inner.mapping, inner.uv_map)
    return None
