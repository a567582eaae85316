"""Which light each leaf of the light tree holds (lights/tree.py). The tree's shape is fixed by its number of leaves:
a complete binary tree in implicit heap order (node j has the children 2j + 1 and 2j + 2, the N leaves are the
nodes N - 1 .. 2N - 2). What is left to choose is the lights' places, and a node's bound is only as good as its
lights are close together: a node holding two lights at opposite ends of the scene has a box the size of the scene,
its importance at a point beside one of them is that of a far-away box, and the descent rarely reaches the light
that lights the point (a pick probability 200 times below its share of the light there gave the tuning garden's
fireflies of the first bounce).

So the lights are split top down as a k-d tree whose cuts fall where the fixed shape needs them: at every internal
node its lights are ordered along the longest side of their centres' box and the first ones, as many as its left
subtree has leaves, go left. Every node then holds the lights of one box cut out of its parent's, which a sort by a
space-filling curve does not give: consecutive lights along the curve jump across the scene wherever a subtree's
range of the sorted order straddles one of the curve's large steps. The build is vectorised by level: one sort of
all lights per level, keyed by node and then by coordinate."""

from __future__ import annotations

import numpy as np


def subtree_leaves(leaves: int) -> np.ndarray:
    """The number of leaves below each node (a leaf: 1) of the complete tree of `leaves` leaves in heap order."""
    total = max(2 * leaves - 1, 1)
    count = np.zeros(total, np.int64)
    count[leaves - 1:] = 1
    for d in range(depth_of(leaves) - 1, -1, -1):
        j = np.arange((1 << d) - 1, min((1 << (d + 1)) - 1, leaves - 1))
        count[j] = count[2 * j + 1] + count[2 * j + 2]
    return count


def depth_of(leaves: int) -> int:
    """The number of levels above the deepest leaves: the least d with 2^d >= leaves."""
    return max(int(leaves) - 1, 0).bit_length()


def leaf_lights(centres: np.ndarray) -> np.ndarray:
    """(N,) for the leaf nodes N - 1 .. 2N - 2 in turn, the index of the point of `centres` (N, 3) it holds."""
    n = len(centres)
    if n == 0:
        return np.zeros(0, np.int64)
    count = subtree_leaves(n)
    start = np.zeros(len(count), np.int64)  # where each node's lights begin in `order`
    order = np.arange(n)
    rows = np.arange(n)
    # every level above the deepest is complete (2^d < n nodes of it): its nodes' ranges of `order` cover it all,
    # left to right
    for d in range(depth_of(n)):
        nodes = np.arange((1 << d) - 1, (1 << (d + 1)) - 1)
        c = centres[order]
        first = start[nodes]
        low = np.minimum.reduceat(c, first, axis=0)
        span = np.maximum.reduceat(c, first, axis=0) - low
        side = np.argmax(span, axis=1)
        node_of = np.repeat(np.arange(len(nodes)), count[nodes])
        # the sort key: the node, then the coordinate along its longest side, as a fraction in [0, 1/2]
        lo_n, span_n = low[np.arange(len(nodes)), side], span[np.arange(len(nodes)), side]
        frac = (c[rows, side[node_of]] - lo_n[node_of]) * (0.5 / np.maximum(span_n, 1e-300))[node_of]
        order = order[np.argsort(node_of + frac)]
        inner = nodes[nodes < n - 1]
        start[2 * inner + 1] = start[inner]
        start[2 * inner + 2] = start[inner] + count[2 * inner + 1]
    return order[start[n - 1:]]
