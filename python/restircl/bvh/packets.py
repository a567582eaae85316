"""Leaf packets: the triangles of each BVH leaf (at most 4) as one SoA record of three Tri slots, which the device
intersects with float4 operations, one triangle per lane (opencl/bvh/traverse.h, BVH_TRI4).

Packet p holds lane-wise x, y, z of v0 (Tri slot 0: in its v0, e1, e2 fields), of e1 (slot 1) and of e2 (slot 2);
unused lanes are NaN, which no ray hits. The packets follow the leaf-ordered Tri array in the same buffer, so
kernels keep their (nodes, tris) arguments and tris[prim] stays the triangle the shading reads. A leaf slot of a
node then holds child = ~(first packet slot) and count = the first triangle of the leaf (its lanes are triangles
first, first + 1, ...).
"""

from __future__ import annotations

import numpy as np

from ..core import layouts

#: most triangles in a leaf the packets can hold (the build's leaf_max must not exceed it)
LANES = 4
#: whether the device traverses leaf packets (device_arrays, defines); else it tests a leaf's triangles one by one
ENABLED = True
#: the build's leaf size (bvh.build_bvh) with packets and without: the faster of those measured for each
#: (docs/measurements/benchmarks.md, "Traversal")
LEAF_MAX = 3
LEAF_MAX_TRIANGLES = 2


def leaf_max() -> int:
    """The build's default leaf size for the traversal that ENABLED selects."""
    return LEAF_MAX if ENABLED else LEAF_MAX_TRIANGLES


def defines() -> dict[str, int]:
    """The -D flags that tell opencl/bvh/traverse.h the layout device_arrays gives."""
    return {"BVH_TRI4": 1} if ENABLED else {}


def device_arrays(nodes: np.ndarray, tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (nodes, tris) arrays to upload for the traversal that defines() selects."""
    return with_packets(nodes, tris) if ENABLED else (nodes, tris)


def with_packets(nodes: np.ndarray, tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(nodes, tris) as the BVH_TRI4 traversal reads them, from build_bvh's nodes and make_tris' triangles."""
    out = nodes.copy()
    child, count = out["child"], out["count"]
    leaf = (child < 0) & (count > 0)
    first = (~child[leaf]).astype(np.int64)
    cnt = count[leaf].astype(np.int64)
    if len(cnt) and int(cnt.max()) > LANES:
        raise ValueError(f"a leaf holds {int(cnt.max())} triangles; packets hold at most {LANES}")
    n, m = len(tris), len(first)
    lanes = first[:, None] + np.arange(LANES)[None, :]
    valid = np.arange(LANES)[None, :] < cnt[:, None]
    src = tris[np.minimum(lanes, max(n - 1, 0))] if n else np.zeros((m, LANES), layouts.TRI)
    pk = np.zeros((m, 3), layouts.TRI)
    flat = pk.view(np.float32).reshape(m, 3, 3, 4)  # packet, slot (v0 / e1 / e2), axis, lane
    for s, field in enumerate(("v0", "e1", "e2")):
        xyz = src[field][..., :3]  # packet, lane, axis
        flat[:, s] = np.where(valid[:, None, :], np.transpose(xyz, (0, 2, 1)), np.float32(np.nan))
    child[leaf] = ~(n + 3 * np.arange(m, dtype=np.int64)).astype(np.int32)
    count[leaf] = first.astype(np.int32)
    return out, np.concatenate([tris, pk.reshape(-1)])
