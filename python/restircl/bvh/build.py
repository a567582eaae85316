"""Bounding volume hierarchy: a binned-SAH BVH built top-down with vectorised numpy, and the triangle array.

The build processes one whole level of a binary tree per step: every node of the level is binned, evaluated and
partitioned by the same array operations, so the Python overhead is per level, not per node. The binary tree is
then numbered depth first and collapsed into 4-wide nodes (bvh/wide.py); node 0 is the root. The device side is
opencl/bvh/traverse.h.

Leaf encoding (see types.h): a child reference c >= 0 is the inner node c; c < 0 is a leaf whose triangles are
tris[~c : ~c + count] (``~c == -c - 1``). The triangles are stored in leaf order (make_tris), depth first, so a
leaf is one contiguous range of the Tri array.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..core import layouts
from . import packets as bvh_packets
from .binning import bin_sah
from .wide import COST_TRI, binary_sah_cost, depth_first, empty_slots, wide_nodes

#: SAH bins per axis
BINS = 8
#: evaluate the SAH on all three axes (else only along the largest centroid extent: faster, about 8% more node
#: visits per ray)
ALL_AXES = True


@dataclass
class BVH:
    nodes: np.ndarray          # layouts.BVH_NODE, node 0 is the root
    order: np.ndarray          # int64: leaf position -> input triangle index
    build_seconds: float
    depth: int = 0             # levels of the binary tree the 4-wide nodes were collapsed from
    leaf_count: int = 0
    sah_cost: float = 0.0      # SAH cost of the binary tree (bvh_wide.binary_sah_cost)

    @property
    def node_count(self) -> int:
        return len(self.nodes)



def device_vertices(v0: np.ndarray, v1: np.ndarray, v2: np.ndarray):
    """float32 (v0, e1, e2) as stored in Tri, and the vertices v1, v2 the device reconstructs as v0 + e1, v0 + e2.

    The edges are differences of the float32-rounded vertices, so v0 + e1 gives back the rounded v1 exactly
    whenever the difference is a float32 (always when the coordinates are within a factor 2 of each other, as
    for small triangles far from the origin): a vertex shared by two triangles then has the same value in both,
    which the watertight intersection test needs. Otherwise it is off by at most one float32 step of the
    triangle's coordinates, which the device's edge tolerance (BVH_EDGE_TOL in bvh/intersect.h) covers. The node boxes
    are computed from these reconstructed vertices, so they hold what the device intersects.
    """
    a = np.asarray(v0, dtype=np.float32)
    b = np.asarray(v1, dtype=np.float32)
    c = np.asarray(v2, dtype=np.float32)
    e1 = (b.astype(np.float64) - a).astype(np.float32)
    e2 = (c.astype(np.float64) - a).astype(np.float32)
    return a, e1, e2, a + e1, a + e2


def make_tris(
    v0: np.ndarray,
    v1: np.ndarray,
    v2: np.ndarray,
    material: np.ndarray,
    prim: np.ndarray,
    order: np.ndarray,
    obj: np.ndarray | None = None,
) -> np.ndarray:
    """The Tri array in leaf order: v0.w = material id, e1.w = prim (the original triangle index), e2.w = obj
    (0 when not given), all as int bits. `order` is BVH.order."""
    order = np.asarray(order, dtype=np.int64)
    a, e1, e2, _, _ = device_vertices(np.asarray(v0)[order], np.asarray(v1)[order], np.asarray(v2)[order])
    out = np.zeros(len(order), dtype=layouts.TRI)
    out["v0"][:, :3] = a
    out["e1"][:, :3] = e1
    out["e2"][:, :3] = e2
    out["v0"][:, 3] = layouts.int_bits(np.asarray(material)[order])
    out["e1"][:, 3] = layouts.int_bits(np.asarray(prim)[order])
    if obj is not None:
        out["e2"][:, 3] = layouts.int_bits(np.asarray(obj)[order])
    return out


class _Nodes:
    """Growable node storage in SoA form (filled level by level)."""

    def __init__(self, capacity: int) -> None:
        self.box = np.zeros((capacity, 3, 4), np.float32)   # [node, axis, (lmin, rmin, lmax, rmax)]
        self.meta = np.zeros((capacity, 4), np.int32)       # left, right, left count, right count
        self.count = 1                                      # node 0: the root

    def alloc(self, k: int) -> np.ndarray:
        first = self.count
        self.count += k
        if self.count > len(self.box):
            cap = max(self.count, 2 * len(self.box))
            self.box = np.concatenate([self.box, np.zeros((cap - len(self.box), 3, 4), np.float32)])
            self.meta = np.concatenate([self.meta, np.zeros((cap - len(self.meta), 4), np.int32)])
        return np.arange(first, self.count, dtype=np.int64)


def _segment_ids(counts: np.ndarray) -> np.ndarray:
    return np.repeat(np.arange(len(counts), dtype=np.int32), counts)


def build_bvh(
    v0: np.ndarray,
    v1: np.ndarray,
    v2: np.ndarray,
    *,
    bins: int | None = None,
    leaf_max: int | None = None,
    all_axes: bool = ALL_AXES,
) -> BVH:
    """Binned-SAH BVH over triangles given as (T, 3) vertex arrays (world space).

    Every node with more than `leaf_max` (default: bvh_packets.leaf_max()) triangles is split at the SAH-best of
    `bins` - 1 planes between its triangles' centroids, on each axis (`all_axes`) or on the axis of largest
    centroid extent (Wald 2007); nodes of up to `leaf_max` triangles are leaves. A node whose centroids all
    coincide is split in two halves, and so is every node deeper than 60 - log2(T) levels, which bounds the depth.
    The binary tree is collapsed into 4-wide nodes. An empty scene gives one root node whose slots are all unused
    (no ray hits anything).
    """
    t_start = time.perf_counter()
    v0, v1, v2 = _checked_vertices(v0, v1, v2)
    n = len(v0)
    leaf_max = max(1, int(bvh_packets.leaf_max() if leaf_max is None else leaf_max))
    bins = max(2, int(BINS if bins is None else bins))
    level = _Level.of_triangles(v0, v1, v2)
    if n <= 1:
        return BVH(_root_only(level), np.arange(n, dtype=np.int64), time.perf_counter() - t_start, 0, n,
                   float(n) * COST_TRI)

    # From this depth on every node is split in halves: the binary tree has at most 60 levels, so the traversal
    # stack (3 entries per 4-wide level, at most MAX_DEPTH4 levels: see bvh/wide.py) cannot overflow.
    depth_limit = max(1, 60 - int(np.ceil(np.log2(n))))
    builder = _Builder(n, leaf_max, bins, all_axes)
    depth = 0
    while (inner := builder.split(level, halve_all=depth >= depth_limit)) is not None:
        level = inner
        depth += 1

    assert builder.cursor == n
    meta = builder.nodes.meta[: builder.nodes.count]
    box = builder.nodes.box[: builder.nodes.count]
    meta, box, order = depth_first(meta, box, builder.order)
    sah = binary_sah_cost(meta, box)
    out, _ = wide_nodes(meta, box)
    return BVH(out, order, time.perf_counter() - t_start, depth + 1, builder.leaf_count, sah)


def _checked_vertices(v0: np.ndarray, v1: np.ndarray, v2: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The vertex arrays as (T, 3) float64, after the checks the device's 32-bit indices and the build need."""
    v0 = np.asarray(v0, dtype=np.float64).reshape(-1, 3)
    v1 = np.asarray(v1, dtype=np.float64).reshape(-1, 3)
    v2 = np.asarray(v2, dtype=np.float64).reshape(-1, 3)
    n = len(v0)
    if not (len(v1) == n and len(v2) == n):
        raise ValueError("v0, v1, v2 must have the same length")
    if n >= 2**31 - 1:
        raise ValueError("too many triangles for 32-bit indices")
    if n and not (np.all(np.isfinite(v0)) and np.all(np.isfinite(v1)) and np.all(np.isfinite(v2))):
        raise ValueError("triangle vertices contain NaN or Inf")
    return v0, v1, v2


@dataclass
class _Level:
    """The triangles still to be placed, grouped by node: one segment per node of the current level of the binary
    tree, in order. Per triangle (structure of arrays, one array per axis): box and centroid, and input index."""

    lo: list[np.ndarray]
    hi: list[np.ndarray]
    ce: list[np.ndarray]
    ids: np.ndarray         # int32: input triangle index
    count: np.ndarray       # int64: triangles per segment, each more than leaf_max
    node: np.ndarray        # int64: the node each segment becomes

    @classmethod
    def of_triangles(cls, v0: np.ndarray, v1: np.ndarray, v2: np.ndarray) -> _Level:
        """All triangles in one segment, the root; their boxes as the device sees them (float32 v0 + e1, v0 + e2)."""
        a, _, _, b, c = device_vertices(v0, v1, v2)
        lo = np.minimum(np.minimum(a, b), c)
        hi = np.maximum(np.maximum(a, b), c)
        lo_ax = [np.ascontiguousarray(lo[:, k]) for k in range(3)]
        hi_ax = [np.ascontiguousarray(hi[:, k]) for k in range(3)]
        ce_ax = [0.5 * lo_ax[k] + 0.5 * hi_ax[k] for k in range(3)]
        n = len(v0)
        return cls(lo_ax, hi_ax, ce_ax, np.arange(n, dtype=np.int32), np.array([n], dtype=np.int64),
                   np.array([0], dtype=np.int64))


def _root_only(level: _Level) -> np.ndarray:
    """The 4-wide root of a scene of at most one triangle: all slots unused but, with one triangle, a leaf in slot 0."""
    out = np.zeros(1, dtype=layouts.BVH_NODE)
    empty_slots(out)
    if len(level.ids):
        out["child"][0, 0] = -1
        out["count"][0, 0] = 1
        for k, ax in enumerate("xyz"):
            out["min" + ax][0, 0] = level.lo[k][0]
            out["max" + ax][0, 0] = level.hi[k][0]
    return out


class _Builder:
    """The binary tree under construction: its nodes, the leaf order of the triangles placed so far."""

    def __init__(self, n: int, leaf_max: int, bins: int, all_axes: bool) -> None:
        self.leaf_max, self.bins, self.all_axes = leaf_max, bins, all_axes
        self.nodes = _Nodes(max(16, (2 * n) // leaf_max + 16))
        self.order = np.empty(n, dtype=np.int64)
        self.cursor = 0  # next free leaf position in `order`
        self.leaf_count = 0

    def split(self, level: _Level, halve_all: bool) -> _Level | None:
        """Split every node of `level` in two (in halves where `halve_all`), write the nodes, place the triangles of
        the children that are leaves; the next level (the inner children), or None when there is none."""
        starts = np.zeros(len(level.count), dtype=np.int64)
        np.cumsum(level.count[:-1], out=starts[1:])
        seg = _segment_ids(level.count)
        right, n_left, boxes = self._partition(level, starts, seg, halve_all)
        n_right = level.count - n_left
        child_count = np.stack([n_left, n_right], 1).reshape(-1)
        child_leaf = child_count <= self.leaf_max
        ref, leaf_first = self._link(level.node, n_left, n_right, boxes, child_count, child_leaf)

        # Rank of every triangle within its child (stable), then its destination: the next level's arrays for
        # inner children, the leaf order for leaves.
        m = len(level.ids)
        left = ~right
        cl = np.cumsum(left, dtype=np.int64)
        cl -= left
        rank = np.where(right, np.arange(m, dtype=np.int64) - starts[seg] - (cl - cl[starts][seg]),
                        cl - cl[starts][seg])
        child = 2 * seg.astype(np.int64) + right
        is_leaf_p = child_leaf[child]
        self._place_leaves(level.ids, child, rank, is_leaf_p, leaf_first, child_count, child_leaf)
        inner_c = np.nonzero(~child_leaf)[0]
        if len(inner_c) == 0:
            return None
        ic = np.where(child_leaf, 0, child_count)
        new_start = np.cumsum(ic) - ic
        src = np.nonzero(~is_leaf_p)[0]
        perm = np.empty(len(src), dtype=np.int64)
        perm[new_start[child[src]] + rank[src]] = src
        return _Level([x[perm] for x in level.lo], [x[perm] for x in level.hi], [x[perm] for x in level.ce],
                      level.ids[perm], child_count[inner_c], ref[inner_c])

    def _partition(self, level: _Level, starts: np.ndarray, seg: np.ndarray, halve_all: bool):
        """Per triangle, whether it goes to the right child; per segment, the left child's count and the children's
        boxes (l_lo, l_hi, r_lo, r_hi: (S, 3) each)."""
        plane, cost_best, n_left, (l_lo, l_hi, r_lo, r_hi), bk = self._best_planes(level, starts, seg)
        # No plane separates the triangles only when all centroids coincide: split by position then (the children
        # get the whole box). Also below the depth limit, to bound the depth.
        halves = ~np.isfinite(cost_best)
        if halve_all:
            halves[:] = True
        right = bk > plane[seg]
        if np.any(halves):
            h = halves[seg]
            pos = np.arange(len(level.ids), dtype=np.int64) - starts[seg]
            right[h] = pos[h] >= (level.count[seg][h] // 2)
            w_lo = np.minimum(l_lo, r_lo)
            w_hi = np.maximum(l_hi, r_hi)
            hh = halves[:, None]
            l_lo, r_lo = np.where(hh, w_lo, l_lo), np.where(hh, w_lo, r_lo)
            l_hi, r_hi = np.where(hh, w_hi, l_hi), np.where(hh, w_hi, r_hi)
        n_left = np.where(halves, level.count // 2, n_left)
        return right, n_left, (l_lo, l_hi, r_lo, r_hi)

    def _best_planes(self, level: _Level, starts: np.ndarray, seg: np.ndarray):
        """bin_sah's answer per segment on the axis of lowest cost (all three, or the largest centroid extent)."""
        S = len(level.count)
        rows = np.arange(S)
        c_lo = np.stack([np.minimum.reduceat(level.ce[k], starts) for k in range(3)], 1)
        c_hi = np.stack([np.maximum.reduceat(level.ce[k], starts) for k in range(3)], 1)
        ext = c_hi - c_lo
        axes = [np.full(S, k) for k in range(3)] if self.all_axes else [np.argmax(ext, axis=1)]
        best = None
        for i, axis in enumerate(axes):
            r = bin_sah(axis, i if self.all_axes else None, ext, c_lo, level.ce, level.lo, level.hi, seg,
                         level.count, S, rows, self.bins)
            if best is None:
                best = list(r)
                continue
            better = r[1] < best[1]  # keep, per segment, the axis of lower cost
            best[0] = np.where(better, r[0], best[0])
            best[1] = np.where(better, r[1], best[1])
            best[2] = np.where(better, r[2], best[2])
            best[3] = tuple(np.where(better[:, None], x, y) for x, y in zip(r[3], best[3], strict=True))
            best[4] = np.where(better[seg], r[4], best[4])
        assert best is not None
        return best

    def _link(self, seg_node: np.ndarray, n_left: np.ndarray, n_right: np.ndarray, boxes, child_count: np.ndarray,
              child_leaf: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Write the level's nodes: the children's boxes, and their references: new nodes for inner children, leaf
        ranges (from the cursor on) for the others. Returns every child's reference and the leaves' first
        positions."""
        l_lo, l_hi, r_lo, r_hi = boxes
        nodes = self.nodes
        for j in range(3):
            nodes.box[seg_node, j, 0] = l_lo[:, j]
            nodes.box[seg_node, j, 2] = l_hi[:, j]
            nodes.box[seg_node, j, 1] = r_lo[:, j]
            nodes.box[seg_node, j, 3] = r_hi[:, j]
        inner_c = np.nonzero(~child_leaf)[0]
        leaf_c = np.nonzero(child_leaf)[0]
        ref = np.empty(len(child_count), dtype=np.int64)
        ref[inner_c] = nodes.alloc(len(inner_c))
        lc = child_count[leaf_c]
        leaf_first = self.cursor + np.cumsum(lc) - lc
        ref[leaf_c] = ~leaf_first
        nodes.meta[seg_node, 0] = ref[0::2]
        nodes.meta[seg_node, 1] = ref[1::2]
        nodes.meta[seg_node, 2] = np.where(child_leaf[0::2], n_left, 0)
        nodes.meta[seg_node, 3] = np.where(child_leaf[1::2], n_right, 0)
        return ref, leaf_first

    def _place_leaves(self, ids: np.ndarray, child: np.ndarray, rank: np.ndarray, is_leaf_p: np.ndarray,
                      leaf_first: np.ndarray, child_count: np.ndarray, child_leaf: np.ndarray) -> None:
        """The triangles of the leaf children into the leaf order, each leaf's in the order of the level."""
        leaf_c = np.nonzero(child_leaf)[0]
        k_leaf = int(child_count[leaf_c].sum())
        if k_leaf:
            leaf_first_full = np.zeros(len(child_count), dtype=np.int64)
            leaf_first_full[leaf_c] = leaf_first
            out_pos = leaf_first_full[child[is_leaf_p]] + rank[is_leaf_p]
            self.order[out_pos] = ids[is_leaf_p]
            self.cursor += k_leaf
            self.leaf_count += len(leaf_c)
