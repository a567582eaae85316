"""The light tree's small subtrees: where a descent reaches a node with at most EXACT lights below it, it picks one of
them directly, each by its own importance at the shading point (lights/tree.py importance of its leaf), instead of
going on by the bounds of boxes. Mirrors opencl/lights/tree_exact.h.

Why: a node's bound cannot tell where in its box its lights are. At a point inside a box (a bounce vertex 0.2 m from
a small lamp that brings it 0.82 of its unshadowed light, in the `user` kind's room of 42 lamps), the nearest point's
share says 1 and the farthest corner's about the power share, so every level of the descent gave the lamp's side
0.73-0.88 and the lamp got 0.49 of the local picks: bright NEE samples of the first frames. A light's own bound is tight
(a point light's box is its sphere), and below a node of a few dozen lights summing them all is cheap beside the
vertex's rays. The probability of light l below such a node j is

    p(l | j) = (1 - F) (N_l / sum N + R_l / sum R) / 2 + F phi_l / phi_j,

N and R the leaf's importance at its box's nearest point and farthest corner (one share alone where the other sum is
0 or not finite, the power share where both are), phi the power, F the tree's floor (pick_floor.FLOOR): the rule of a
branch (lights/tree.py branch) over all the node's lights at once; summed over l it is 1. Unlike a branch it is not
clamped to pick_floor.MIN_BRANCH: a light whose share and power share in its node are both below about 1e-7 may be
missed by the float uniform that the pdf still counts (a bias of at most such a light's part of the light)."""

from __future__ import annotations

import numpy as np

from .pick_floor import mixed

#: a node with at most this many lights below it picks among them by their own importance (opencl/codes.h
#: LIGHT_TREE_EXACT)
EXACT = 32

#: ... where the point is near it: its distance to the node's box at most NEAR times the box's diagonal (opencl/codes.h
#: LIGHT_TREE_NEAR, used by opencl/lights/tree_exact.h). Near or inside a box its bound cannot tell its lights apart;
#: far from it the descent's branches already follow the lights' shares, and summing up to EXACT leaves there costs
#: CPU for little (600 lights of the `interior` kind: docs/measurements/error-vs-time.md, the adaptive exact pick).
NEAR = 0.25


def near_nodes(lo: np.ndarray, hi: np.ndarray, x: np.ndarray, near: float) -> np.ndarray:
    """Per node (boxes lo..hi, (M, 3)), whether x is within `near` times the box's diagonal of the box (float32 as on
    the device, so both take the same decision to float rounding: a point within an ulp of the bound may differ)."""
    lo, hi, x = lo.astype(np.float32), hi.astype(np.float32), np.asarray(x, np.float32)
    d = np.maximum(np.maximum(lo - x, x - hi), np.float32(0))
    diag = hi - lo
    f = np.float32(near)
    return np.einsum("ij,ij->i", d, d) <= f * f * np.einsum("ij,ij->i", diag, diag)


def subtree_leaf_nodes(j: int, leaves: int) -> np.ndarray:
    """The leaf nodes below node j (j itself if a leaf) of the complete tree of `leaves` leaves in heap order, level
    by level and left to right: the order in which the device walks them (lights/tree_exact.h)."""
    last, inner = 2 * leaves - 2, leaves - 1
    out: list[int] = []
    first, width = j, 1
    while first <= last:
        m = np.arange(first, min(first + width, last + 1))
        out.extend(m[m >= inner].tolist())
        first, width = 2 * first + 1, 2 * width
    return np.array(out, np.int64)


def exact_shares(near: np.ndarray, far: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """p(l | j) of the lights below a node, given their leaves' near and far importances and powers."""
    parts = [v / v.sum() for v in (near, far) if v.sum() > 0 and np.isfinite(v.sum())]
    power = phi / phi.sum()
    share = sum(parts) / len(parts) if parts else power
    return mixed(share, power)
