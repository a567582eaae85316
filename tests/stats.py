"""Statistical helpers for the tests: a chi-square goodness-of-fit test with pooled low-expectation bins, and the
comparison of a Monte Carlo mean with an expected image within its standard errors (disagreement)."""

from __future__ import annotations

import math

import numpy as np
from scipy import stats

from .helpers import allowed_outliers


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


Z = 4.0  # standard errors of disagreement's bounds


def normal_outliers(n: int, z: float = Z) -> int:
    """How many of n independent normal z-scores may exceed z: the expected count plus four of its standard
    deviations (binomial), plus one."""
    p = math.erfc(z / math.sqrt(2.0))
    return int(math.ceil(n * p + 4 * math.sqrt(n * p * (1 - p)) + 1))


def disagreement(mean: np.ndarray, se: np.ndarray, expected: np.ndarray, *, batches: int | None = None,
                 exact_rtol: float = 1e-9, judged: np.ndarray | None = None) -> list[str]:
    """Why `mean` (..., 3) with standard errors `se` is not `expected`, or [] where it is: each value of `judged`
    (default all) within Z standard errors but for the allowed outliers (normal z-scores; t-scores of `batches`
    batch means where given), to exact_rtol where its se is 0; and the mean over all values of each channel within Z
    standard errors of it. A value whose sample variance cannot be trusted (a few rare hits) is left to the image
    mean by `judged`."""
    judged = np.broadcast_to(np.ones(1, bool) if judged is None else judged, mean.shape)
    exact = (se <= 1e-9 * np.abs(expected) + 1e-15) & judged
    noisy = ~exact & judged
    problems = []
    if not np.allclose(mean[exact], expected[exact], rtol=exact_rtol, atol=1e-12):
        problems.append(f"exact values differ by up to {np.abs(mean - expected)[exact].max():.3g}")
    z = np.abs(mean - expected) / np.where(exact, 1.0, np.maximum(se, 1e-300))
    n = int(noisy.sum())
    out = int((z[noisy] > Z).sum())
    if out > (normal_outliers(n) if batches is None else allowed_outliers(n, batches)):
        problems.append(f"{out} of {n} values beyond {Z} standard errors (largest z {z[noisy].max():.2f})")
    flat = (mean - expected).reshape(-1, 3)
    pooled = np.sqrt((se.reshape(-1, 3) ** 2).sum(axis=0)) / len(flat)
    image_z = np.abs(flat.mean(axis=0)) / np.maximum(pooled, 1e-300)
    if np.any((image_z > Z) & (pooled > 0)):
        problems.append(f"image means {image_z.round(2)} standard errors off")
    return problems


def weighted_image_bias(runs: np.ndarray, ref: np.ndarray, ref_se: np.ndarray) -> tuple[float, float]:
    """Relative bias of independent runs (runs, H, W) against a reference image (mean, standard error) over the
    image, each pixel weighted by 1 / (its standard deviation over runs), and its standard error.

    Why weighted: the plain image mean is ruled by the noisiest pixels (a few bright ones under ReSTIR's heavy
    tails); weighting by inverse deviation lets the many quiet pixels speak (on the occluder scene, the biased ReSTIR
    mode: the standard error 0.4-0.5 % instead of 0.8-2 % at 24 runs). Why cross-fitted: weights taken from the
    same runs they weigh favour runs that came out low (a bright outlier raises its pixel's deviation and lowers
    its own weight); each half of the runs is weighed by the other half's deviations, so every weight is
    independent of the values it weighs and the mean stays unbiased. Runs of one half are independent given the
    weights: the standard error combines the two halves' sample variances and the reference's."""
    halves = (runs[: len(runs) // 2], runs[len(runs) // 2:])
    means, variances = [], []
    for k, half in enumerate(halves):
        sd = halves[1 - k].std(axis=0, ddof=1)
        live = (sd > 1e-9 * np.abs(ref)) & (ref_se > 1e-9 * np.abs(ref))
        w = np.where(live, 1.0 / np.where(live, sd, 1.0), 0.0)
        level = float((w * ref).sum())
        per_run = ((half - ref) * w).sum(axis=(1, 2)) / level
        means.append(float(per_run.mean()))
        variances.append(float(per_run.var(ddof=1)) / len(per_run) + float(((w * ref_se) ** 2).sum()) / level**2)
    return 0.5 * (means[0] + means[1]), 0.5 * math.sqrt(variances[0] + variances[1])
