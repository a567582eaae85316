"""Colour attributes of meshes (Mesh.attributes) for the Attribute texture nodes (materials/textures.py): the names
the materials read, each an index, and per triangle a block of their corner colours after the TriAttr records of
the device (opencl/textures/point.h, TriAttr.tangent.w: the block's offset in float4s; opencl/textures/nodes.h reads
it). A mesh without an attribute of that name holds zeros there, as Cycles reads a missing attribute."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from ..core import layouts as L
from ..materials import textures as tx
from ..materials.material import Material, material_inputs
from ..scene.scene import Scene, WorldTriangles


def texture_nodes(m: Material) -> list[object]:
    """Every texture node under m's inputs, each once."""
    stack, seen, out = [v for v in material_inputs(m) if tx.is_texture(v)], set(), []
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        out.append(node)
        stack.extend(getattr(node, f.name) for f in fields(node) if tx.is_texture(getattr(node, f.name)))
    return out


def attribute_names(materials: list[Material]) -> list[str]:
    """The names the materials' Attribute nodes read, sorted: a name's index is its place in each triangle's block
    and in its nodes' records (upload/textures.py)."""
    return sorted({n.name for m in materials for n in texture_nodes(m) if isinstance(n, tx.Attribute)})


def attribute_rows(scene: Scene, world: WorldTriangles, order: np.ndarray, names: list[str],
                   records: np.ndarray) -> np.ndarray:
    """The (T * K * 3, 4) float32 corner colours of the K `names` for the triangles in BVH leaf order (`order`), to
    follow the TriAttr `records` (one per triangle, in that order) in the device buffer; each record's tangent.w is
    set to its block's offset in float4s from the buffer's start."""
    n, k = len(order), len(names)
    if not k or not n:
        return np.zeros((0, 4), np.float32)
    rows = np.zeros((n, k, 3, 4), np.float32)
    obj, prim = world.object[order], world.prim[order]
    for m, mesh in enumerate(scene.meshes):
        sel = np.nonzero(obj == m)[0]
        for j, name in enumerate(names):
            a = (mesh.attributes or {}).get(name)
            if a is not None and len(sel):
                rows[sel, j] = np.asarray(a, np.float32)[prim[sel]]
    start = len(records) * (L.TRI_ATTR.itemsize // 16)
    records["tangent"][:n, 3] = L.int_bits(start + 3 * k * np.arange(n))
    return rows.reshape(-1, 4)
