"""The (t, k, s)-net property of a point set, the measure of a quasi-random sampler's stratification: 2^k points in
[0, 1)^s are a (t, k, s)-net when every elementary box of volume 2^-(k - t) (a product of dyadic intervals
[a 2^-d, (a + 1) 2^-d), one per coordinate, the depths d adding up to k - t) holds exactly 2^t of them.

Written from the definition alone, on the points' bits, so that the tests of the Sobol sampler
(tests/render/test_qmc.py, test_qmc_camera.py) and the layout probe (tools/experiments/sobol_net_layouts.py) check
the points without any of the sampler's code."""

from __future__ import annotations

from itertools import combinations

import numpy as np


def net_holds(points: np.ndarray, k: int, t: int) -> bool:
    """Whether `points` (2^k rows of s coordinates as 32-bit fractions: integers below 2^32) are a (t, k, s)-net."""
    p = np.asarray(points).astype(np.uint64)
    if p.ndim != 2 or len(p) != 1 << k or not 0 <= t <= k:
        raise ValueError(f"2^{k} points of s coordinates and 0 <= t <= k wanted, got {p.shape} and t = {t}")
    m, s = k - t, p.shape[1]
    for cuts in combinations(range(m + s - 1), s - 1):  # the compositions of m into s parts (stars and bars)
        depths = np.diff((-1, *cuts, m + s - 1)) - 1
        cell = np.zeros(len(p), np.int64)
        for col, d in enumerate(depths):
            if d:
                cell = (cell << int(d)) + (p[:, col] >> np.uint64(32 - d)).astype(np.int64)
        if np.bincount(cell, minlength=1 << m).max() != 1 << t:
            return False
    return True


def t_value(points: np.ndarray, k: int) -> int:
    """The smallest t for which `points` (2^k of them) are a (t, k, s)-net; any 2^k points are a (k, k, s)-net."""
    return next(t for t in range(k + 1) if net_holds(points, k, t))
