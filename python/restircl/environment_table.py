"""Importance-sampling tables of the environment light (opencl/lights/environment.h): texel i is drawn with
probability proportional to luminance_i x solid angle_i, first its row from a marginal table, then its column from
that row's conditional table, then a direction uniform in solid angle inside the texel. The density in solid angle
is then constant over a texel: pdf = P(row) P(column | row) / solid angle of the texel.

Two kinds of table, measured against each other on PoCL (docs/benchmarks.md):
- "cdf": the marginal and the conditional cumulative distributions, searched by bisection (log2 H + log2 W reads);
- "alias": Walker's alias tables for the marginal and each row (two reads each, whatever the size).

Both are flat float32 arrays the device reads from the light buffer (environment.py places them there)."""

from __future__ import annotations

import numpy as np

TABLE_KINDS = ("alias", "cdf")


def row_solid_angles(height: int, width: int) -> np.ndarray:
    """(H,) float64: the solid angle of one texel of each row of an equirectangular map, row 0 at the zenith."""
    edges = np.cos(np.pi * np.arange(height + 1) / height)
    return (edges[:-1] - edges[1:]) * (2.0 * np.pi / width)


def texel_weights(luminance: np.ndarray) -> np.ndarray:
    """(H, W) float64 luminance x texel solid angle: what the tables sample proportionally to."""
    h, w = luminance.shape
    return np.asarray(luminance, np.float64) * row_solid_angles(h, w)[:, None]


def alias_rows(weights: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Walker's alias table of every row of (R, N) non-negative weights at once: (prob, alias), each (R, N).

    Entry k of a row keeps itself with probability prob[k] and otherwise gives its alias, so that entry i is
    drawn with probability weights[i] / sum(weights) when k is uniform. Rows are paired up in lock step (one
    small entry with one large entry per step, N steps for all rows together); each row is sorted first, so the
    small entries are taken from the left and the large ones from the right. A row of zeros gets a uniform table
    (it is never drawn: its marginal probability is 0)."""
    w = np.asarray(weights, np.float64)
    rows, n = w.shape
    total = w.sum(axis=1, keepdims=True)
    q = np.where(total > 0, w * n / np.where(total > 0, total, 1.0), 1.0)
    order = np.argsort(q, axis=1, kind="stable")
    q = np.take_along_axis(q, order, axis=1)  # sorted: small entries left, large right
    prob = np.ones((rows, n))
    alias = np.tile(np.arange(n), (rows, 1))
    r = np.arange(rows)
    lo = np.zeros(rows, np.int64)  # the next small entry from the left
    hi = np.full(rows, n - 1, np.int64)  # the current large entry
    for _ in range(n - 1):
        active = lo < hi
        if not np.any(active):
            break
        demoted = active & (q[r, hi] < 1.0)  # the large entry fell below 1: it is the next small entry
        small = np.where(demoted, hi, lo)
        large = np.where(demoted, hi - 1, hi)
        a = r[active]
        s, g = small[active], large[active]
        prob[a, s] = q[a, s]
        alias[a, s] = g
        q[a, g] -= 1.0 - q[a, s]
        lo = np.where(active & ~demoted, lo + 1, lo)
        hi = np.where(demoted, hi - 1, hi)
    prob = np.clip(prob, 0.0, 1.0)
    # back to the rows' own order: entry order[k] got (prob[k], order[alias[k]])
    out_prob = np.empty_like(prob)
    out_alias = np.empty_like(alias)
    np.put_along_axis(out_prob, order, prob, axis=1)
    np.put_along_axis(out_alias, order, np.take_along_axis(order, alias, axis=1), axis=1)
    return out_prob, out_alias


def alias_probabilities(prob: np.ndarray, alias: np.ndarray) -> np.ndarray:
    """What an alias table draws (R, N): the probability of each entry (for tests)."""
    rows, n = prob.shape
    p = prob / n
    r = np.repeat(np.arange(rows), n)
    np.add.at(p, (r, alias.reshape(-1)), ((1.0 - prob) / n).reshape(-1))
    return p


def _cdf(weights: np.ndarray) -> np.ndarray:
    """(R, N) weights -> (R, N + 1) cumulative distributions from 0 to 1 (uniform for a row of zeros)."""
    w = np.asarray(weights, np.float64)
    c = np.concatenate([np.zeros((w.shape[0], 1)), np.cumsum(w, axis=1)], axis=1)
    total = c[:, -1:]
    uniform = np.linspace(0.0, 1.0, w.shape[1] + 1)[None, :]
    c = np.where(total > 0, c / np.where(total > 0, total, 1.0), uniform)
    c[:, -1] = 1.0
    return c


def build_table(luminance: np.ndarray, kind: str) -> np.ndarray:
    """The flat float32 table of an (H, W) luminance map (layout in opencl/lights/environment.h):
    alias: H (prob, alias bits) pairs of the rows, then H x W pairs of the rows' columns;
    cdf: H + 1 entries of the rows' cumulative distribution, then H rows of W + 1 of the columns'."""
    weights = texel_weights(luminance)
    h, w = weights.shape
    rows = weights.sum(axis=1)
    if kind == "alias":
        out = np.empty(2 * h + 2 * h * w, np.float32)
        mp, ma = alias_rows(rows[None, :])
        cp, ca = alias_rows(weights)
        pairs = out.reshape(-1, 2)
        pairs[:h, 0] = mp[0]
        pairs[:h, 1] = ma[0].astype(np.int32).view(np.float32)
        pairs[h:, 0] = cp.reshape(-1)
        pairs[h:, 1] = ca.reshape(-1).astype(np.int32).view(np.float32)
        return out
    if kind == "cdf":
        return np.concatenate([_cdf(rows[None, :]).reshape(-1), _cdf(weights).reshape(-1)]).astype(np.float32)
    raise ValueError(f"environment table kind must be one of {TABLE_KINDS}, got {kind!r}")


def table_texel_probabilities(table: np.ndarray, height: int, width: int, kind: str) -> np.ndarray:
    """(H, W) probability of each texel that the device's table draws (for tests)."""
    if kind == "alias":
        pairs = table.reshape(-1, 2)
        mp, ma = pairs[:height, 0:1].T.astype(np.float64), pairs[:height, 1:2].T.view(np.int32)
        cp = pairs[height:, 0].reshape(height, width).astype(np.float64)
        ca = pairs[height:, 1].copy().view(np.int32).reshape(height, width)
        return alias_probabilities(mp, ma)[0][:, None] * alias_probabilities(cp, ca)
    marg = table[: height + 1].astype(np.float64)
    cond = table[height + 1:].reshape(height, width + 1).astype(np.float64)
    return np.diff(marg)[:, None] * np.diff(cond, axis=1)
