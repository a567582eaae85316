"""What the light tree (tree.py) knows of each light: a box, a cone of emission and whether it emits on both
sides. Each light type computes them from its own records (LightType.bounds, read through the registry); a type whose
lights have no position says so with DISTANT, and the tree picks its lights outside the descent."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Literal

import numpy as np

#: LightType.bounds of a type whose lights have no position (the sun, the environment): not in the tree
DISTANT: Final = "distant"
Distant = Literal["distant"]


@dataclass
class Bounds:
    """Per light of one type, k of them: lo, hi (k, 3) a box holding every point of the light; axis (k, 3) unit and
    theta_o (k,) radians: a cone holding its emission normals; theta_e (k,): how far beyond the normals it still
    emits; two_sided (k,) bool: it emits along -axis too."""

    lo: np.ndarray
    hi: np.ndarray
    axis: np.ndarray
    theta_o: np.ndarray
    theta_e: np.ndarray
    two_sided: np.ndarray


def omnidirectional(lo: np.ndarray, hi: np.ndarray) -> Bounds:
    """Lights in these boxes that emit in every direction (normals over the whole sphere, one-sided)."""
    k = len(lo)
    return Bounds(lo, hi, np.tile([0.0, 0.0, 1.0], (k, 1)), np.full(k, np.pi), np.full(k, 0.5 * np.pi),
                  np.zeros(k, bool))
