"""Statistical helpers for the tests: a chi-square goodness-of-fit test with pooled low-expectation bins."""

from __future__ import annotations

import numpy as np
from scipy import stats


def pooled_chi2(observed: np.ndarray, expected_prob: np.ndarray, min_expected: float = 5.0) -> tuple[float, float, int]:
    """Chi-square test of counts against bin probabilities. Bins expecting fewer than `min_expected` counts are
    pooled (in ascending order of expectation) until each pooled bin expects at least that many. Observed counts
    in bins of probability 0 make the test fail outright (p = 0). Returns (statistic, p-value, dof)."""
    obs = np.asarray(observed, dtype=np.float64).ravel()
    p = np.asarray(expected_prob, dtype=np.float64).ravel()
    n = obs.sum()
    if np.any(obs[p <= 0] > 0):
        return float("inf"), 0.0, 0
    keep = p > 0
    obs, exp = obs[keep], p[keep] / p[keep].sum() * n
    order = np.argsort(exp)
    obs, exp = obs[order], exp[order]
    pooled_o, pooled_e = [], []
    acc_o = acc_e = 0.0
    for o, e in zip(obs, exp, strict=True):
        acc_o += o
        acc_e += e
        if acc_e >= min_expected:
            pooled_o.append(acc_o)
            pooled_e.append(acc_e)
            acc_o = acc_e = 0.0
    if acc_e > 0:
        if pooled_e:
            pooled_o[-1] += acc_o
            pooled_e[-1] += acc_e
        else:
            pooled_o.append(acc_o)
            pooled_e.append(acc_e)
    po, pe = np.array(pooled_o), np.array(pooled_e)
    dof = len(po) - 1
    if dof < 1:
        return 0.0, 1.0, 0
    stat = float(((po - pe) ** 2 / pe).sum())
    return stat, float(stats.chi2.sf(stat, dof)), dof
