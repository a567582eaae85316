"""The floor of the light tree's pick probabilities, shared by its branches (lights/tree.py branch) and by the
split between the tree and the distant lights (lights/distant_pick.py): every probability is the importance
share mixed with the power (or fixed) share by FLOOR, so that a light the importance bound rules out at a point
stays reachable (the bounds ignore shading normals), and clamped away from 0 and 1. The device reads the same
constants (opencl/codes.h LIGHT_TREE_FLOOR, LIGHT_TREE_MIN_BRANCH)."""

from __future__ import annotations

from typing import TypeVar

import numpy as np

#: share of each pick probability given by the power or fixed share (lights/tree.h LIGHT_TREE_FLOOR)
FLOOR = 0.1
#: no pick probability below this, nor above 1 minus it (lights/tree.h LIGHT_TREE_MIN_BRANCH)
MIN_BRANCH = 1.0 / 4096.0

#: a float, or numpy arrays of them
Share = TypeVar("Share", float, np.ndarray)


def mixed(share: Share, fixed: Share) -> Share:
    """An importance `share` mixed with the power or fixed share `fixed` by FLOOR (lights/tree.h
    light_pick_floored): the exact pick's probabilities (lights/tree_exact.py), unclamped."""
    return (1.0 - FLOOR) * share + FLOOR * fixed


def floored(share: float, fixed: float) -> float:
    """The probability from an importance `share` and the power or fixed share `fixed`: mixed by FLOOR, clamped."""
    return min(max(mixed(share, fixed), MIN_BRANCH), 1.0 - MIN_BRANCH)
