"""The light tree: a spatial proposal for RIS candidates (DESIGN section 3; the idea of pbrt-v4's BVHLightSampler and
Cycles' light tree, written here for our light records). Mirrors opencl/lights/tree.h.

Every light with a position and power > 0 is a leaf of a binary tree stored in implicit heap order (node j has the
children 2j + 1 and 2j + 2; the N leaves are nodes N - 1 .. 2N - 2), the lights placed on the leaves by cuts of
space (lights/tree_leaves.py), so that every node's lights are neighbours. A node bounds its lights by
a box, a cone of emission normals (axis, theta_o, plus theta_e: how far beyond the normals they still emit), their
summed power and whether any is two-sided. The device descends from the root choosing each child with probability
proportional to an importance bound at the shading point, mixed with the children's power share (a floor: every
emitting light keeps a nonzero probability whatever the bound says), down to a node of at most tree_exact.EXACT
lights, where it picks one of them by each light's own importance (lights/tree_exact.py). A light's leaf index is
also its trail: the binary digits of leaf + 1 below the leading one are the branches taken, so the pmf of a given
light at a given point is the product of the branch probabilities along it down to the first node of few lights,
times the light's share there.

Each light's box and cone come from its type (LightType.bounds, lights/<type>.py, through the registry); the lights
of a type without a position (bounds DISTANT: the sun, the environment) stay outside the tree, as Cycles keeps distant
lights; a pick goes to them or to the tree by their fixed shares weighed at the shading point by what can reach it
(lights/distant_pick.py). A record of a code no type has is an error, not a distant light."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core import layouts as L
from ..settings.table import Settings
from .bounds import DISTANT
from .distant_pick import distant_importance, distant_shares, distant_table, local_share
from .pick_floor import floored
from .registry import groups
from .tree_exact import EXACT, NEAR, exact_shares, near_nodes, subtree_leaf_nodes
from .tree_leaves import leaf_lights, subtree_leaves

NODE_TWO_SIDED = 1  # lights/tree.h LIGHT_TREE_TWO_SIDED: a light below the node emits on both sides


@dataclass
class LightBounds:
    """Per light: where it is and how it faces. lo/hi (N, 3) box; axis (N, 3) unit; theta_o, theta_e (N,)
    radians; phi (N,) power; two_sided (N,) bool; local (N,) bool: has a position (a candidate for the tree)."""

    lo: np.ndarray
    hi: np.ndarray
    axis: np.ndarray
    theta_o: np.ndarray
    theta_e: np.ndarray
    phi: np.ndarray
    two_sided: np.ndarray
    local: np.ndarray


@dataclass
class LightTree:
    nodes: np.ndarray  # layouts.LIGHT_TREE_NODE, 2 * leaves - 1 (one placeholder when there are no leaves)
    light_info: np.ndarray  # (N, 2) int32 per light: leaf node index (-1: not in the tree), its row of `distant` if not
    distant: np.ndarray  # (D, distant_pick.LANES) int32: the distant lights' table (lights/distant_pick.py)
    leaves: int
    p_local: float  # the tree's share of the light array: the floor of the local share at a point (distant_pick.py)

    @property
    def distant_count(self) -> int:
        return len(self.distant)


def light_bounds(records: np.ndarray, types: np.ndarray, power: np.ndarray) -> LightBounds:
    """Bounds of each light record (layouts.LIGHT), as its type computes them (LightType.bounds, lights/<type>.py);
    the lights of a DISTANT type have none (lo, hi NaN) and are not local."""
    lanes = records.view(np.float32).reshape(-1, 16).astype(np.float64)
    flags = records.view(np.int32).reshape(-1, 16)[:, 15]
    n = len(lanes)
    lo, hi = np.full((n, 3), np.nan), np.full((n, 3), np.nan)
    axis = np.tile([0.0, 0.0, 1.0], (n, 1))
    theta_o = np.full(n, np.pi)
    theta_e = np.full(n, 0.5 * np.pi)
    two_sided = np.zeros(n, bool)
    spatial = np.zeros(n, bool)
    for t, sel in groups(types) if n else ():
        if t.bounds == DISTANT:
            continue
        b = t.bounds(lanes[sel], flags[sel])
        lo[sel], hi[sel], axis[sel] = b.lo, b.hi, b.axis
        theta_o[sel], theta_e[sel], two_sided[sel] = b.theta_o, b.theta_e, b.two_sided
        spatial[sel] = True
    phi = np.asarray(power, np.float64)
    emits = np.isfinite(phi) & (phi > 0)
    local = spatial & emits & np.all(np.isfinite(lo) & np.isfinite(hi), axis=1)
    return LightBounds(lo, hi, axis, theta_o, theta_e, np.where(emits, phi, 0.0), two_sided, local)


def merge_cones(wa: np.ndarray, ta: np.ndarray, wb: np.ndarray, tb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The smallest cone (axis, half angle) holding both cones, per row (vectorised)."""
    swap = tb > ta
    wa, wb = np.where(swap[:, None], wb, wa), np.where(swap[:, None], wa, wb)
    ta, tb = np.where(swap, tb, ta), np.where(swap, ta, tb)  # now ta >= tb
    td = np.arccos(np.clip(np.einsum("ij,ij->i", wa, wb), -1.0, 1.0))
    inside = np.minimum(td + tb, np.pi) <= ta
    to = 0.5 * (ta + td + tb)
    k = np.cross(wa, wb)
    klen = np.linalg.norm(k, axis=1)
    full = (to >= np.pi) | ((klen < 1e-12) & ~inside)
    tr = to - ta
    k = k / np.maximum(klen, 1e-300)[:, None]
    rotated = wa * np.cos(tr)[:, None] + np.cross(k, wa) * np.sin(tr)[:, None]
    rotated /= np.maximum(np.linalg.norm(rotated, axis=1), 1e-300)[:, None]
    axis = np.where(inside[:, None] | full[:, None], wa, rotated)
    theta = np.where(inside, ta, np.where(full, np.pi, to))
    return axis, theta


def build_light_tree(records: np.ndarray, types: np.ndarray, power: np.ndarray,
                     array_pdf: np.ndarray | None = None) -> LightTree:
    """The tree over the lights (layouts.LIGHT records with their LIGHT_* types and light-array power). The
    lights outside it and the tree have fixed shares, those the light array gives them (array_pdf: its pdf per
    light; without it, their power share), weighed at a point by what can reach it (lights/distant_pick.py): a
    sun's power is not comparable with a lamp's, and by power alone a sun lighting a wall head-on could get a share
    of 1e-5."""
    bnd = light_bounds(records, types, power)
    n = len(bnd.phi)
    local = np.flatnonzero(bnd.local)
    leaves = len(local)
    total = max(2 * leaves - 1, 1)
    lo, hi = np.zeros((total, 3)), np.zeros((total, 3))
    axis = np.tile([0.0, 0.0, 1.0], (total, 1))
    theta_o, theta_e, phi = np.full(total, np.pi), np.zeros(total), np.zeros(total)
    two_sided = np.zeros(total, bool)
    light = np.full(total, -1, np.int64)
    info = np.zeros((n, 2), np.int32)
    info[:, 0] = -1
    if leaves:
        sorted_lights = local[leaf_lights(0.5 * (bnd.lo[local] + bnd.hi[local]))]
        slots = np.arange(leaves - 1, 2 * leaves - 1)
        light[slots] = sorted_lights
        for dst, src in ((lo, bnd.lo), (hi, bnd.hi), (axis, bnd.axis)):
            dst[slots] = src[sorted_lights]
        for dst1, src1 in ((theta_o, bnd.theta_o), (theta_e, bnd.theta_e), (phi, bnd.phi),
                           (two_sided, bnd.two_sided)):
            dst1[slots] = src1[sorted_lights]
        info[sorted_lights, 0] = slots
        _fill_internal(leaves, lo, hi, axis, theta_o, theta_e, phi, two_sided)
    nodes = np.zeros(total, L.LIGHT_TREE_NODE)
    nodes["lo"][:, :3], nodes["lo"][:, 3] = lo, phi
    nodes["hi"][:, :3], nodes["hi"][:, 3] = hi, np.cos(theta_o)
    nodes["axis"][:, :3], nodes["axis"][:, 3] = axis, np.cos(theta_e)
    nodes["meta"][:, 0], nodes["meta"][:, 1] = light, np.where(two_sided, NODE_TWO_SIDED, 0)
    nodes["meta"][:, 2] = np.sin(theta_o).astype(np.float32).view(np.int32)
    nodes["meta"][:, 3] = subtree_leaves(leaves) if leaves else 0  # below a node of few, the exact pick
    # distant lights (nothing else outside the tree emits), in order
    emits = bnd.phi > 0
    far = np.flatnonzero(emits & ~bnd.local)
    weight = bnd.phi if array_pdf is None else np.asarray(array_pdf, np.float64)
    total_weight = weight[emits].sum()
    p_local = float(1.0 - weight[far].sum() / total_weight) if len(far) and total_weight > 0 else 1.0
    if leaves == 0:
        p_local = 0.0
    fixed = weight[far] / max(weight[far].sum(), 1e-300)
    info[far, 1] = np.arange(len(far))
    distant = distant_table(far, records, types, fixed, (1.0 - p_local) * fixed)
    return LightTree(nodes, info, distant, leaves, p_local)


def _fill_internal(leaves: int, lo, hi, axis, theta_o, theta_e, phi, two_sided) -> None:
    """Bounds of the internal nodes 0 .. leaves - 2 from their children, one heap level at a time (deepest
    first: children have the larger indices)."""
    last = leaves - 2
    if last < 0:
        return
    top = int(np.floor(np.log2(last + 1)))
    for level in range(top, -1, -1):
        j = np.arange((1 << level) - 1, min((1 << (level + 1)) - 1, last + 1))
        c0, c1 = 2 * j + 1, 2 * j + 2
        lo[j] = np.minimum(lo[c0], lo[c1])
        hi[j] = np.maximum(hi[c0], hi[c1])
        axis[j], theta_o[j] = merge_cones(axis[c0], theta_o[c0], axis[c1], theta_o[c1])
        theta_e[j] = np.maximum(theta_e[c0], theta_e[c1])
        phi[j] = phi[c0] + phi[c1]
        two_sided[j] = two_sided[c0] | two_sided[c1]


def tree_pays(types: np.ndarray) -> bool:
    """light_proposal="auto": whether the tree beats the light array at equal time for lights of these types.
    Not yet anywhere measured: on the 2-core CPU (PoCL) a tree candidate halved RIS's per-frame error on the
    tuning garden (300 point lights) but cost 2.5-4x an array candidate, and gave 10 % on neon; at equal time the
    array won on both (docs/measurements/benchmarks.md, "Light tree"). On few lights stills pick from the per-pixel
    table (lights/pick_table.py, up to 64 lights), a better proposal than the tree's bound, and on studio the tree's
    candidates proposed worse than the array's even with the stratified descent of Sobol words
    (docs/measurements/error-vs-time.md, "Few lights, one factor at a time"). Nor where the array is at its worst:
    on lamp fields of 1k-10k point lights spread over 100-400 m the tree's candidates have 4-5x less error per
    frame, but cost 4-6x as much, which leaves it at 0.7-1.3x the array's efficiency, within the spread of the seeds
    (error-vs-time.md, "Light tree on lamp fields"). So auto keeps the array until a device measures otherwise."""
    return False


def tree_proposal(method: str, proposal: str, types: np.ndarray) -> bool:
    """Whether the RIS candidates of a render with this method and Settings.light_proposal come from the tree, for
    lights of these LIGHT_* types."""
    if method not in ("ris", "restir") or proposal in ("array", "pixel") or len(types) < 2:
        return False
    return proposal == "tree" or tree_pays(types)


def path_tree_pays(types: np.ndarray) -> bool:
    """path_light_pick="auto": whether NEE at path vertices picks from the tree rather than the light array. A
    vertex draws one light, where a pixel's direct light draws several candidates (whose RIS finds the good ones
    among cheap array picks), and a bounce reaches surfaces that most lights do not face or barely reach (walls far
    from most spots): measured on the tuning room (eval/scenes/gi_tuning.py), docs/measurements/error-vs-time.md,
    "Global illumination against Cycles"."""
    return len(types) >= 2


def path_tree(pick: str, candidates_tree: bool, types: np.ndarray) -> bool:
    """Whether NEE at path vertices picks from the light tree, for Settings.path_light_pick, lights of these LIGHT_*
    types, and whether the RIS candidates already take theirs from it (auto then keeps it)."""
    if pick == "array" or len(types) < 2:
        return False
    return pick == "tree" or candidates_tree or path_tree_pays(types)


def light_trees(settings: Settings, types: np.ndarray) -> tuple[bool, bool]:
    """(RIS candidates from the tree, NEE at path vertices from the tree) for a renderer with these settings and
    lights of these LIGHT_* types; the tree is built where either is true."""
    s = settings
    candidates = tree_proposal(s.method, s.light_proposal, types)
    return candidates, s.max_bounces > 0 and path_tree(s.path_light_pick, candidates, types)


# ---- the host's reference of the device's branch probabilities (tests; opencl/lights/tree.h) ----------------



def _cos_sub(cos_a, sin_a, cos_b, sin_b):
    """cos and sin of max(0, a - b) for angles in [0, pi] given by their cos and sin."""
    inside = cos_a >= cos_b
    c = np.where(inside, 1.0, cos_a * cos_b + sin_a * sin_b)
    s = np.where(inside, 0.0, sin_a * cos_b - cos_a * sin_b)
    return c, s


def importance(nodes: np.ndarray, x: np.ndarray, n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each node's importance at point x with unit normal n at the distance of its box's nearest point and of its
    farthest corner (lights/tree.h light_tree_importance; float64, the device computes it in float)."""
    lo, hi = nodes["lo"][:, :3].astype(np.float64), nodes["hi"][:, :3].astype(np.float64)
    phi, cos_o, cos_e = (nodes[k][:, 3].astype(np.float64) for k in ("lo", "hi", "axis"))
    sin_o = nodes["meta"][:, 2].copy().view(np.float32).astype(np.float64)
    ax = nodes["axis"][:, :3].astype(np.float64)
    two = (nodes["meta"][:, 1] & NODE_TWO_SIDED) != 0
    d = x - 0.5 * (lo + hi)
    near = np.maximum(np.abs(d) - 0.5 * (hi - lo), 0.0)  # per axis, from the box's near face (0 between the faces)
    far = np.abs(d) + 0.5 * (hi - lo)  # ... and from its far face
    inv_near = 1.0 / np.maximum(np.einsum("ij,ij->i", near, near), 1e-12)
    inv_far = 1.0 / np.maximum(np.einsum("ij,ij->i", far, far), 1e-12)
    d2 = np.einsum("ij,ij->i", d, d)
    r2 = 0.25 * np.einsum("ij,ij->i", hi - lo, hi - lo)
    inside = d2 <= r2
    wo = d / np.sqrt(np.maximum(d2, 1e-300))[:, None]  # from the node towards x
    sin2_b = np.where(inside, 0.0, r2 / np.maximum(d2, 1e-300))
    cos_b, sin_b = np.sqrt(np.maximum(0.0, 1 - sin2_b)), np.sqrt(sin2_b)
    cos_i = -np.einsum("j,ij->i", n, wo)
    cos_ip, _ = _cos_sub(cos_i, np.sqrt(np.maximum(0.0, 1 - cos_i**2)), cos_b, sin_b)
    cos_w = np.einsum("ij,ij->i", ax, wo)
    cos_w = np.where(two, np.abs(cos_w), cos_w)
    c1, s1 = _cos_sub(cos_w, np.sqrt(np.maximum(0.0, 1 - cos_w**2)), cos_o, sin_o)
    cos_p, _ = _cos_sub(c1, s1, cos_b, sin_b)
    cos_p = np.where(cos_o > -1, cos_p, 1.0)
    bound = np.where(inside, phi, np.where((cos_p < cos_e) | (cos_ip <= 0), 0.0, phi * cos_ip * cos_p))
    return bound * inv_near, bound * inv_far


def pmf(tree: LightTree, x: np.ndarray, n: np.ndarray) -> np.ndarray:
    """The probability with which the device's pick chooses each light at (x, n), every light (float64)."""
    out = np.zeros(len(tree.light_info))
    far = tree.light_info[:, 0] < 0
    x, n = np.asarray(x, np.float64), np.asarray(n, np.float64)
    near_imp, far_imp = importance(tree.nodes, x, n)
    p_local = local_pick_share(tree, n, near_imp[0])
    if tree.distant_count:
        out[tree.distant[:, 0]] = (1.0 - p_local) * distant_shares(tree.distant, n)
    if tree.leaves == 0:
        return out
    phi = tree.nodes["lo"][:, 3].astype(np.float64)
    count = tree.nodes["meta"][:, 3]
    prob = np.ones(len(tree.nodes))
    near = near_nodes(tree.nodes["lo"][:, :3], tree.nodes["hi"][:, :3], x, NEAR)
    stack = [0]  # parents before children
    while stack:
        j = stack.pop()
        if j >= tree.leaves - 1:
            continue
        if count[j] <= EXACT and near[j]:  # the lights below picked by their own importance (lights/tree_exact.py)
            below = subtree_leaf_nodes(j, tree.leaves)
            prob[below] = prob[j] * exact_shares(near_imp[below], far_imp[below], phi[below])
            continue
        c0, c1 = 2 * j + 1, 2 * j + 2
        p0 = branch((near_imp[c0], far_imp[c0]), (near_imp[c1], far_imp[c1]), phi[c0], phi[c1])
        prob[c0], prob[c1] = prob[j] * p0, prob[j] * (1 - p0)
        stack += [c0, c1]
    leaf = tree.light_info[~far, 0]
    out[~far] = p_local * prob[leaf]
    return out


def local_pick_share(tree: LightTree, n: np.ndarray, root: float) -> float:
    """The probability that a pick at a point of normal n descends the tree (lights/distant_pick.py), root: the
    root's importance there at its box's nearest point."""
    if tree.distant_count == 0:
        return 1.0
    if tree.leaves == 0:
        return 0.0
    return local_share(root, float(distant_importance(tree.distant, n).sum()), tree.p_local)


def _share(a: float, b: float) -> float | None:
    s = a + b
    return a / s if s > 0 and np.isfinite(s) else None


def branch(i0: tuple[float, float], i1: tuple[float, float], phi0: float, phi1: float) -> float:
    """The probability of the first child (lights/tree.h light_tree_branch) of children of (near, far) importances
    i0, i1 and powers phi0, phi1."""
    if not (phi0 > 0 and phi1 > 0):
        return 1.0 if phi0 > 0 else 0.0
    pw = phi0 / (phi0 + phi1)
    shares = [v for v in (_share(i0[0], i1[0]), _share(i0[1], i1[1])) if v is not None]
    return floored(sum(shares) / len(shares) if shares else pw, pw)
