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
    triangle's coordinates, which the device's edge tolerance (BVH_EDGE_TOL in bvh/traverse.h) covers. The node boxes
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


def _prefix(x: np.ndarray, op) -> np.ndarray:
    """Running op over the rows of x (row by row: numpy's accumulate along axis 0 is strided and slow)."""
    out = np.empty_like(x)
    out[0] = x[0]
    for i in range(1, len(x)):
        op(out[i - 1], x[i], out=out[i])
    return out


def _suffix(x: np.ndarray, op) -> np.ndarray:
    out = np.empty_like(x)
    out[-1] = x[-1]
    for i in range(len(x) - 2, -1, -1):
        op(out[i + 1], x[i], out=out[i])
    return out


def _bin_sah(axis, single, ext, c_lo, ce_ax, lo_ax, hi_ax, seg, seg_count, S, rows, bins):
    """Bin every segment's centroids along `axis` (per segment; `single`: the same axis for all) and sweep the
    SAH over the bins - 1 planes. Returns, per segment, the best plane, its cost, the left count and the
    children's boxes (lo, hi: (S, 3) for left and right), and the bin of every triangle."""
    e_ax = ext[rows, axis].astype(np.float64)
    scale = np.where(e_ax > 0, bins * (1.0 - 1e-6) / np.where(e_ax > 0, e_ax, 1.0), 0.0).astype(np.float32)
    lo_sel = c_lo[rows, axis]
    c_sel = ce_ax[single] if single is not None else np.choose(axis[seg], ce_ax)
    bk = ((c_sel - lo_sel[seg]) * scale[seg]).astype(np.int32)
    np.clip(bk, 0, bins - 1, out=bk)
    # Per (bin, segment): triangle count and box; bin-major, so that the sweeps run over contiguous rows.
    nb = S * bins
    key = bk * np.int32(S) + seg
    cnt = np.bincount(key, minlength=nb).reshape(bins, S)
    nl = np.cumsum(cnt[:-1], axis=0, dtype=np.int64)
    nr = seg_count[None, :] - nl
    pre_lo, pre_hi, suf_lo, suf_hi = [], [], [], []
    for j in range(3):
        t = np.full(nb, np.inf, np.float32)
        np.minimum.at(t, key, lo_ax[j])
        t = t.reshape(bins, S)
        u = np.full(nb, -np.inf, np.float32)
        np.maximum.at(u, key, hi_ax[j])
        u = u.reshape(bins, S)
        pre_lo.append(_prefix(t, np.minimum))
        pre_hi.append(_prefix(u, np.maximum))
        suf_lo.append(_suffix(t, np.minimum))
        suf_hi.append(_suffix(u, np.maximum))
    with np.errstate(invalid="ignore", over="ignore"):
        dl = [pre_hi[j][:-1] - pre_lo[j][:-1] for j in range(3)]
        dr = [suf_hi[j][1:] - suf_lo[j][1:] for j in range(3)]
        al = dl[0] * dl[1] + dl[1] * dl[2] + dl[2] * dl[0]
        ar = dr[0] * dr[1] + dr[1] * dr[2] + dr[2] * dr[0]
        costs = al * nl + ar * nr
    costs[(nl == 0) | (nr == 0)] = np.inf
    plane = np.argmin(costs, axis=0)
    pr = np.minimum(plane + 1, bins - 1)
    boxes = tuple(np.stack([a[j][p, rows] for j in range(3)], 1)
                  for a, p in ((pre_lo, plane), (pre_hi, plane), (suf_lo, pr), (suf_hi, pr)))
    return plane, costs[plane, rows], nl[np.minimum(plane, bins - 2), rows], boxes, bk


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
    leaf_max = max(1, int(bvh_packets.leaf_max() if leaf_max is None else leaf_max))
    bins = max(2, int(BINS if bins is None else bins))

    # Boxes of the triangles as the device sees them (float32 v0 + e1, v0 + e2).
    a, _, _, b, c = device_vertices(v0, v1, v2)
    lo = np.minimum(np.minimum(a, b), c)
    hi = np.maximum(np.maximum(a, b), c)
    del a, b, c
    # Per-triangle data of the triangles still to be placed, grouped by node (segments), structure of arrays.
    lo_ax = [np.ascontiguousarray(lo[:, k]) for k in range(3)]
    hi_ax = [np.ascontiguousarray(hi[:, k]) for k in range(3)]
    ce_ax = [0.5 * lo_ax[k] + 0.5 * hi_ax[k] for k in range(3)]
    ids = np.arange(n, dtype=np.int32)
    del lo, hi

    order = np.empty(n, dtype=np.int64)
    nodes = _Nodes(max(16, (2 * n) // leaf_max + 16))
    if n <= 1:
        out = np.zeros(1, dtype=layouts.BVH_NODE)
        empty_slots(out)
        if n:  # one leaf in slot 0
            order[0] = 0
            out["child"][0, 0] = -1
            out["count"][0, 0] = 1
            for k, ax in enumerate("xyz"):
                out["min" + ax][0, 0] = lo_ax[k][0]
                out["max" + ax][0, 0] = hi_ax[k][0]
        return BVH(out, order, time.perf_counter() - t_start, 0, n, float(n) * COST_TRI)

    # From this depth on every node is split in halves: the binary tree has at most 60 levels, so the traversal
    # stack (3 entries per 4-wide level, at most MAX_DEPTH4 levels: see bvh/wide.py) cannot overflow.
    depth_limit = max(1, 60 - int(np.ceil(np.log2(n))))
    cursor = 0                                    # next free leaf position in `order`
    seg_count = np.array([n], dtype=np.int64)     # one segment per node of the current level, all inner
    seg_node = np.array([0], dtype=np.int64)      # the node each segment becomes
    depth = 0
    leaf_count = 0
    while len(seg_count):
        S = len(seg_count)
        m = len(ids)
        starts = np.zeros(S, dtype=np.int64)
        np.cumsum(seg_count[:-1], out=starts[1:])
        seg = _segment_ids(seg_count)
        rows = np.arange(S)

        # Bin the centroids along the axis of largest centroid extent of each segment.
        c_lo = np.stack([np.minimum.reduceat(ce_ax[k], starts) for k in range(3)], 1)
        c_hi = np.stack([np.maximum.reduceat(ce_ax[k], starts) for k in range(3)], 1)
        ext = c_hi - c_lo
        axes = [np.full(S, k) for k in range(3)] if all_axes else [np.argmax(ext, axis=1)]
        best = None
        for i, axis in enumerate(axes):
            r = _bin_sah(axis, i if all_axes else None, ext, c_lo, ce_ax, lo_ax, hi_ax, seg, seg_count, S, rows,
                         bins)
            if best is None:
                best = list(r)
                continue
            better = r[1] < best[1]  # keep, per segment, the axis of lower cost
            best[0] = np.where(better, r[0], best[0])
            best[1] = np.where(better, r[1], best[1])
            best[2] = np.where(better, r[2], best[2])
            best[3] = tuple(np.where(better[:, None], x, y) for x, y in zip(r[3], best[3], strict=True))
            best[4] = np.where(better[seg], r[4], best[4])
        plane, cost_best, n_left, (l_lo, l_hi, r_lo, r_hi), bk = best
        # No plane separates the triangles only when all centroids coincide: split by position then (the children
        # get the whole box). Also below depth_limit, to bound the depth.
        halves = ~np.isfinite(cost_best)
        if depth >= depth_limit:
            halves[:] = True
        right = bk > plane[seg]
        if np.any(halves):
            h = halves[seg]
            pos = np.arange(m, dtype=np.int64) - starts[seg]
            right[h] = pos[h] >= (seg_count[seg][h] // 2)
            w_lo = np.minimum(l_lo, r_lo)
            w_hi = np.maximum(l_hi, r_hi)
            hh = halves[:, None]
            l_lo, r_lo = np.where(hh, w_lo, l_lo), np.where(hh, w_lo, r_lo)
            l_hi, r_hi = np.where(hh, w_hi, l_hi), np.where(hh, w_hi, r_hi)
        n_left = np.where(halves, seg_count // 2, n_left)
        n_right = seg_count - n_left
        child_count = np.stack([n_left, n_right], 1).reshape(-1)
        child_leaf = child_count <= leaf_max
        for j in range(3):
            nodes.box[seg_node, j, 0] = l_lo[:, j]
            nodes.box[seg_node, j, 2] = l_hi[:, j]
            nodes.box[seg_node, j, 1] = r_lo[:, j]
            nodes.box[seg_node, j, 3] = r_hi[:, j]

        # References: new nodes for inner children, leaf ranges for the others.
        inner_c = np.nonzero(~child_leaf)[0]
        leaf_c = np.nonzero(child_leaf)[0]
        ref = np.empty(2 * S, dtype=np.int64)
        ref[inner_c] = nodes.alloc(len(inner_c))
        lc = child_count[leaf_c]
        leaf_first = cursor + np.cumsum(lc) - lc
        ref[leaf_c] = ~leaf_first
        nodes.meta[seg_node, 0] = ref[0::2]
        nodes.meta[seg_node, 1] = ref[1::2]
        nodes.meta[seg_node, 2] = np.where(child_leaf[0::2], n_left, 0)
        nodes.meta[seg_node, 3] = np.where(child_leaf[1::2], n_right, 0)

        # Rank of every triangle within its child (stable), then its destination: the next level's arrays for
        # inner children, the leaf order for leaves.
        left = ~right
        cl = np.cumsum(left, dtype=np.int64)
        cl -= left
        rank = np.where(right, np.arange(m, dtype=np.int64) - starts[seg] - (cl - cl[starts][seg]),
                        cl - cl[starts][seg])
        child = 2 * seg.astype(np.int64) + right
        is_leaf_p = child_leaf[child]
        k_leaf = int(lc.sum())
        if k_leaf:
            out_pos = leaf_first_full = np.zeros(2 * S, dtype=np.int64)
            leaf_first_full[leaf_c] = leaf_first
            out_pos = leaf_first_full[child[is_leaf_p]] + rank[is_leaf_p]
            order[out_pos] = ids[is_leaf_p]
            cursor += k_leaf
            leaf_count += len(leaf_c)
        if len(inner_c) == 0:
            break
        ic = np.where(child_leaf, 0, child_count)
        new_start = np.cumsum(ic) - ic
        keep = ~is_leaf_p
        src = np.nonzero(keep)[0]
        perm = np.empty(len(src), dtype=np.int64)
        perm[new_start[child[src]] + rank[src]] = src
        for arrs in (lo_ax, hi_ax, ce_ax):
            for k in range(3):
                arrs[k] = arrs[k][perm]
        ids = ids[perm]
        seg_count = child_count[inner_c]
        seg_node = ref[inner_c]
        depth += 1

    assert cursor == n
    meta = nodes.meta[: nodes.count]
    box = nodes.box[: nodes.count]
    meta, box, order = depth_first(meta, box, order)
    sah = binary_sah_cost(meta, box)
    out, _ = wide_nodes(meta, box)
    return BVH(out, order, time.perf_counter() - t_start, depth + 1, leaf_count, sah)
