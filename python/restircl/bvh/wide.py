"""Wide BVH layout: the binary tree of the SAH build (bvh/build.py) numbered depth first and collapsed into the 4-wide
nodes of opencl/types.h, and the SAH cost of the binary tree.

Each 4-wide node holds the boxes of up to four children in SoA form: its binary children, opened down to four
children; node 0 is the root. Depth-first numbering makes a subtree one contiguous range of nodes and of
triangles (the device side is opencl/bvh/traverse.h).
"""

from __future__ import annotations

import numpy as np

from ..core import layouts

#: most levels of 4-wide nodes the greedy collapse may give (else both binary children are opened): with 3 stack
#: entries per level this bounds the traversal stack (BVH_STACK_SIZE in bvh/traverse.h)
MAX_DEPTH4 = 30
#: SAH cost of visiting one binary inner node, in units of one triangle test (for BVH.sah_cost)
COST_NODE = 1.0
COST_TRI = 1.0


def _area(x0, x1, y0, y1, z0, z1):
    dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
    return dx * dy + dy * dz + dz * dx


def wide_nodes(meta: np.ndarray, box: np.ndarray) -> tuple[np.ndarray, int]:
    """The 4-wide nodes of the depth-first numbered binary tree and their number of levels: the greedy collapse,
    unless it gives more than MAX_DEPTH4 levels."""
    out, depth4 = collapse4(meta, box, greedy=True)
    if depth4 > MAX_DEPTH4:
        out, depth4 = collapse4(meta, box, greedy=False)
    return out, depth4


def empty_slots(out: np.ndarray) -> None:
    """Mark every slot of the 4-wide nodes unused: an empty leaf with an empty box."""
    out["child"] = -1
    out["count"] = 0
    for ax in "xyz":
        out["min" + ax] = np.inf
        out["max" + ax] = -np.inf


def binary_sah_cost(meta: np.ndarray, box: np.ndarray) -> float:
    """SAH cost of the binary tree: COST_NODE per inner node visit, COST_TRI per triangle test."""
    b = box.astype(np.float64)
    root = _area(np.minimum(b[0, 0, 0], b[0, 0, 1]), np.maximum(b[0, 0, 2], b[0, 0, 3]),
                 np.minimum(b[0, 1, 0], b[0, 1, 1]), np.maximum(b[0, 1, 2], b[0, 1, 3]),
                 np.minimum(b[0, 2, 0], b[0, 2, 1]), np.maximum(b[0, 2, 2], b[0, 2, 3]))
    if not root > 0:
        return COST_NODE
    cost = COST_NODE
    for side in (0, 1):
        a = _area(b[:, 0, side], b[:, 0, side + 2], b[:, 1, side], b[:, 1, side + 2], b[:, 2, side],
                  b[:, 2, side + 2])
        cost += float(np.sum(np.where(meta[:, side] >= 0, COST_NODE, COST_TRI * meta[:, side + 2]) * a)) / root
    return cost


def collapse4(meta: np.ndarray, box: np.ndarray, greedy: bool = True) -> tuple[np.ndarray, int]:
    """4-wide nodes from the depth-first numbered binary tree, and their number of levels. A 4-wide node starts
    with its binary node's two children; then (greedy) twice the inner child of largest surface area is replaced
    by its two children, or (not greedy) both inner children are: every 4-wide level then spans two binary
    levels, so the 4-wide tree has at most half the binary tree's levels. The binary nodes kept as 4-wide nodes,
    taken in their depth-first order, are numbered depth first in the 4-wide tree too."""
    n2 = len(meta)
    # Every binary child as (node, side) -> flat id 2 * node + side: reference, count, box, area (-1: leaf).
    ref_c = meta[:, :2].reshape(-1).astype(np.int64)
    cnt_c = np.where(ref_c >= 0, 0, meta[:, 2:].reshape(-1))
    lo_c = np.stack([box[:, :, 0], box[:, :, 1]], 1).reshape(-1, 3)
    hi_c = np.stack([box[:, :, 2], box[:, :, 3]], 1).reshape(-1, 3)
    d = (hi_c - lo_c).astype(np.float64)
    area_c = np.where(ref_c >= 0, d[:, 0] * d[:, 1] + d[:, 1] * d[:, 2] + d[:, 2] * d[:, 0], -1.0)
    slots = np.full((n2, 4), -1, np.int64)  # flat child ids per kept node; -1: unused
    keep = np.zeros(n2, bool)
    keep[0] = True
    frontier = np.array([0], np.int64)
    levels = 0
    while len(frontier):
        levels += 1
        f = frontier
        rows = np.arange(len(f))
        sl = np.full((len(f), 4), -1, np.int64)
        sl[:, 0] = 2 * f
        sl[:, 1] = 2 * f + 1
        first = np.zeros((len(f), 4), bool)  # slots still holding one of the binary node's own children
        first[:, :2] = True
        for free in (2, 3):
            ar = np.where(sl >= 0, area_c[np.maximum(sl, 0)], -1.0)
            if not greedy:
                ar = np.where(first, ar, -1.0)
            k = np.argmax(ar, axis=1)
            ok = ar[rows, k] >= 0  # an inner child to open
            r, kk = rows[ok], k[ok]
            c = ref_c[sl[r, kk]]
            sl[r, free] = 2 * c + 1
            sl[r, kk] = 2 * c
            first[r, kk] = False
        slots[f] = sl
        refs = np.where(sl >= 0, ref_c[np.maximum(sl, 0)], -1).reshape(-1)
        frontier = refs[refs >= 0]
        keep[frontier] = True
    kept = np.nonzero(keep)[0]
    new_index = np.full(n2, -1, np.int64)
    new_index[kept] = np.arange(len(kept))
    sl = slots[kept]
    used = sl >= 0
    slc = np.maximum(sl, 0)
    ref = ref_c[slc]
    out = np.zeros(len(kept), dtype=layouts.BVH_NODE)
    out["child"] = np.where(used, np.where(ref >= 0, new_index[np.maximum(ref, 0)], ref), -1)
    out["count"] = np.where(used, cnt_c[slc], 0)
    lo, hi = lo_c[slc], hi_c[slc]
    for k, ax in enumerate("xyz"):
        out["min" + ax] = np.where(used, lo[:, :, k], np.inf)
        out["max" + ax] = np.where(used, hi[:, :, k], -np.inf)
    return out, levels


def depth_first(meta: np.ndarray, box: np.ndarray, order: np.ndarray):
    """Renumber the nodes (built level by level) in depth-first order, left child first, and put the leaves'
    triangles in the same order: a subtree is then one contiguous range of nodes and of triangles."""
    n_nodes = len(meta)
    left, right = meta[:, 0].astype(np.int64), meta[:, 1].astype(np.int64)
    inner_l, inner_r = left >= 0, right >= 0
    # Levels: children have larger indices than their parents (nodes are allocated level by level).
    level = np.zeros(n_nodes, np.int64)
    frontier = np.array([0])
    levels = [frontier]
    while True:
        ch = np.concatenate([left[frontier][inner_l[frontier]], right[frontier][inner_r[frontier]]])
        if len(ch) == 0:
            break
        level[ch] = len(levels)
        frontier = np.sort(ch)
        levels.append(frontier)
    # Subtree sizes (nodes and triangles), bottom-up.
    size = np.ones(n_nodes, np.int64)
    tris = np.zeros(n_nodes, np.int64)
    for lv in reversed(levels):
        lc, rc = left[lv], right[lv]
        il, ir = inner_l[lv], inner_r[lv]
        size[lv] = 1 + np.where(il, size[np.maximum(lc, 0)], 0) + np.where(ir, size[np.maximum(rc, 0)], 0)
        tris[lv] = (np.where(il, tris[np.maximum(lc, 0)], meta[lv, 2])
                    + np.where(ir, tris[np.maximum(rc, 0)], meta[lv, 3]))
    # New node numbers and triangle ranges, top-down.
    new = np.zeros(n_nodes, np.int64)
    start = np.zeros(n_nodes, np.int64)  # first triangle of the subtree in the new order
    new_meta = meta.copy()
    src_first, dst_first, counts = [], [], []
    for lv in levels:
        lc, rc = left[lv], right[lv]
        il, ir = inner_l[lv], inner_r[lv]
        k, s = new[lv], start[lv]
        n_left_tris = np.where(il, tris[np.maximum(lc, 0)], meta[lv, 2])
        new[lc[il]] = k[il] + 1
        start[lc[il]] = s[il]
        new[rc[ir]] = (k + 1 + np.where(il, size[np.maximum(lc, 0)], 0))[ir]
        start[rc[ir]] = (s + n_left_tris)[ir]
        for side, inner, child, first in ((0, il, lc, s), (1, ir, rc, s + n_left_tris)):
            leaf = ~inner
            src_first.append(~child[leaf])
            dst_first.append(first[leaf])
            counts.append(meta[lv, side + 2][leaf])
            col = new_meta[lv, side]
            col[leaf] = ~first[leaf]
            new_meta[lv, side] = col
    src_first, dst_first, counts = (np.concatenate(x).astype(np.int64) for x in (src_first, dst_first, counts))
    rep = np.repeat(np.arange(len(counts)), counts)
    offs = np.arange(len(rep)) - np.repeat(np.cumsum(counts) - counts, counts)
    new_order = np.empty_like(order)
    new_order[dst_first[rep] + offs] = order[src_first[rep] + offs]
    # Child references to the new node numbers.
    for side in (0, 1):
        c = new_meta[:, side]
        inner = meta[:, side] >= 0
        c[inner] = new[meta[inner, side]]
        new_meta[:, side] = c
    perm = np.empty(n_nodes, np.int64)
    perm[new] = np.arange(n_nodes)
    return new_meta[perm], box[perm], new_order
