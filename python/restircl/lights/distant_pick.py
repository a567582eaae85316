"""The distant lights (suns, the world) beside the light tree: which of the two a pick takes, and which distant light,
by what can reach the shading point. Mirrors opencl/lights/distant_pick.h.

The lights without a position stay outside the tree (lights/tree.py), each with a fixed share of the picks: its
share of the light array (power over a disk of the scene's radius against the lamps' power). That share is spent
also where the light cannot reach: on a sun behind the surface, on the lamps where every one is behind it. So at a
point each share is weighed by the bound of its incidence cosine there: a sun's by the cosine from the normal to
its cone (0 behind the surface), the world's by 1 (some of it lies above every surface), the tree's by 1 where the
root's importance is above 0 (lights/tree.h light_tree_importance: some lamp may reach the point), else 0; the
weighed shares normalised, mixed with the fixed shares by the tree's floor (every light stays reachable, as under
shading normals). A light's probability never drops below its fixed share times its cosine bound, relative to the
rest: a sun's sample never weighs more than under the fixed share, at any angle, and the lamps' picks grow where the
sun lights the surface at a slant or not at all.

Weighed in the tree's own unit instead (the distant lights as the root's sibling, their power over the squared scene
radius against the root's importance, as Cycles' light tree weighs them), the lamps took 0.92-0.93 of the picks in
the `user` room, where the root's bound knows no walls, and rare large samples came that the fixed shares did not
give (docs/measurements/error-vs-time.md, "Distant lights picked at the point")."""

from __future__ import annotations

import numpy as np

from .pick_floor import FLOOR, floored
from .sun import TYPE as SUN

#: lanes of a row of the distant lights' table (int32; float lanes as their bits)
LANES = 8
#: lane 3 of a light that lights every direction (the world): no cone to test
NO_CONE = -2.0


def distant_table(far: np.ndarray, records: np.ndarray, types: np.ndarray, fixed: np.ndarray,
                  array_share: np.ndarray) -> np.ndarray:
    """(D, LANES) int32 rows of the distant lights `far` (indices into the records): 0 the light, 1 its fixed share
    among the distant lights (float bits), 2 its share of all the light array's picks, 3 the cosine of its cone's
    half angle (NO_CONE: the world), 4-6 the direction towards it, 7 the sine of the half angle."""
    table = np.zeros((len(far), LANES), np.int32)
    lanes = records.view(np.float32).reshape(-1, 16)[far].astype(np.float64)
    sun = np.asarray(types)[far] == SUN.code
    cos_half = np.where(sun, lanes[:, 8], NO_CONE)
    towards = np.where(sun[:, None], lanes[:, 4:7], 0.0)
    sin_half = np.sqrt(np.maximum(0.0, 1.0 - np.clip(lanes[:, 8], -1.0, 1.0) ** 2))
    lanes_1_7 = [fixed, array_share, cos_half, *towards.T, np.where(sun, sin_half, 0.0)]
    floats = np.stack(lanes_1_7, axis=1).astype(np.float32)
    table[:, 0] = far
    table[:, 1:] = floats.view(np.int32)
    return table


def _floats(table: np.ndarray, lane: int) -> np.ndarray:
    return table[:, lane].copy().view(np.float32).astype(np.float64)


def distant_importance(table: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Each distant light's share of the light array weighed by its incidence bound at a surface of normal n (2 n:
    one that takes light from both sides, as lights/tree.h light_tree_importance reads it)."""
    n = np.asarray(n, np.float64)
    weight, cos_half, sin_half = _floats(table, 2), _floats(table, 3), _floats(table, 7)
    towards = np.stack([_floats(table, k) for k in (4, 5, 6)], axis=1)
    cos_i = towards @ n
    if n @ n > 2.0:
        cos_i = np.abs(0.5 * cos_i)
    sin_i = np.sqrt(np.maximum(0.0, 1.0 - cos_i * cos_i))
    inside = cos_i >= cos_half
    bound = np.where(inside, 1.0, cos_i * cos_half + sin_i * sin_half)
    return np.where(cos_half <= -1.5, weight, weight * np.maximum(bound, 0.0))


def distant_shares(table: np.ndarray, n: np.ndarray) -> np.ndarray:
    """The probability of each distant light once the pick has gone to the distant lights."""
    imp = distant_importance(table, n)
    fixed = _floats(table, 1)
    total = imp.sum()
    if not (total > 0 and np.isfinite(total)):
        return fixed
    return (1.0 - FLOOR) * imp / total + FLOOR * fixed


def local_share(root: float, distant: float, fixed: float) -> float:
    """The probability of a descent of the tree: root, the root's importance at the point (at the box's nearest
    point); distant, the distant lights' summed distant_importance; fixed, the tree's share of the light array."""
    local = fixed if root > 0 else 0.0
    total = local + distant
    return floored(local / total if total > 0 and np.isfinite(total) else fixed, fixed)
