"""The relMSE of a still render's mean estimated from its two half buffers, with no reference
(StillAccumulation.error_estimate; measured in docs/measurements/error-vs-time.md, "Error while rendering, without a
reference").

The halves a and b are independent estimates of the converged image r, so per pixel and channel (a - b)^2 n_a n_b / n^2
is an unbiased estimate of the variance of the mean, whatever the samples' distribution (one firefly in a half gives
exactly the error it puts in the mean). What needs care is r^2 in relMSE's denominator (r^2 + 0.01):

- a * b is unbiased for r^2 (independent halves, each of mean r); the square of their harmonic mean is never above
  it (with the same floor, the estimate read 1.57x the true error at 16 frames on `garden` with bounces, 1.17x
  with a * b);
- a firefly in one half inflates a * b and the mean alike: with r^2 from them its pixel's term stays near 4 where
  the truth is up to 100x more (so weighed, the estimate read 0.05-0.3 of the error of `outdoor` with bounces and
  0.02-0.13 of `uniform`'s on many_lights). A firefly stands above its 8 neighbours, a pixel of a bright feature
  (a lamp a few pixels wide, an edge) has one as bright: r is taken no higher than the brightest neighbour's mean,
  or than the pixel's smaller half where that is higher (a bright pixel alone whose halves agree keeps its level).
  Fireflies side by side (a caustic) still vouch for each other: there the estimate stays low;
- where a * b is 0 or small (a sub-pixel light met in one half only) r^2 is floored at R2_FLOOR x the mean^2, the
  mean capped by its brightest neighbour's (a lamp hit in one half only has one as bright, a firefly has not); but
  where a half is exactly 0 nothing tells a light that covers a little of the pixel from a firefly over black, and
  the floor keeps the mean (the pixel's term is then at most 1 / R2_FLOOR with halves of equal size).

Cost: a dozen array operations on the image (cheap beside a frame; target_error runs it every 4 frames).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

R2_FLOOR = 0.25  # r^2 is taken as at least R2_FLOOR * mean^2 (the mean capped as above)

R2Rule = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]  # (a, b, mean) (H, W, 3) -> r^2


def _max3(x: np.ndarray, axis: int, centre: bool = True) -> np.ndarray:
    """Per element the largest of its two neighbours along `axis` and, if `centre`, itself (none beyond the border;
    x >= 0)."""
    out = x.copy() if centre else np.zeros_like(x)
    after, before = [slice(None)] * x.ndim, [slice(None)] * x.ndim
    after[axis], before[axis] = slice(1, None), slice(None, -1)
    np.maximum(out[tuple(after)], x[tuple(before)], out=out[tuple(after)])
    np.maximum(out[tuple(before)], x[tuple(after)], out=out[tuple(before)])
    return out


def neighbours_max(x: np.ndarray) -> np.ndarray:
    """(H, W, C): per pixel the largest of its 8 neighbours' values, itself excluded (x >= 0): the 3 x 3 maximum of
    the rows above and below, and the pixels left and right."""
    rows = _max3(x, 1)
    return np.maximum(_max3(rows, 0, centre=False), _max3(x, 1, centre=False))


def robust_r2(a: np.ndarray, b: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """r^2 of relMSE's denominator from the halves a, b and their mean (H, W, 3), as the module says."""
    near = neighbours_max(mean)
    low = np.minimum(a, b)
    cap = np.maximum(near, low)
    r2 = np.minimum(np.maximum(a * b, 0.0), cap * cap)
    floor = np.where(low > 0, np.minimum(mean, near), mean)
    return np.maximum(r2, R2_FLOOR * floor * floor)


def rel_mse_from_halves(a: np.ndarray, b: np.ndarray, n_a: int, n_b: int, r2: R2Rule = robust_r2) -> float:
    """relMSE of the mean of halves a, b (H, W, 3) of n_a and n_b samples; `r2` gives the denominator's r^2."""
    n = n_a + n_b
    mean = (n_a * a + n_b * b) / n
    var_mean = (a - b) ** 2 * (n_a * n_b) / (n * n)
    return float(np.mean(var_mean / (r2(a, b, mean) + 0.01)))
