"""Importance-sampling tables of the environment light (opencl/lights/environment.h): texel i is drawn with
probability proportional to luminance_i x solid angle_i, first its row from a marginal table, then its column from
that row's conditional table, then a direction uniform in solid angle inside the texel. The density in solid angle
is then constant over a texel: pdf = P(row) P(column | row) / solid angle of the texel.

Two kinds of table, measured against each other on PoCL (docs/measurements/benchmarks.md):
- "cdf": the marginal and the conditional cumulative distributions, searched by bisection (log2 H + log2 W reads);
- "alias": Walker's alias tables for the marginal and each row (two reads each, whatever the size).

Both are flat float32 arrays the device reads from the light buffer (environment.py places them there), built
in bands of rows into the light buffer's own array (fill_table), so that a huge map needs no float64 copy of itself."""

from __future__ import annotations

from typing import Protocol

import numpy as np

TABLE_KINDS = ("alias", "cdf")
#: texels per band of rows in the cdf build (float64 only for a band at a time)
CHUNK_TEXELS = 1 << 21
#: texels per band of the alias build: its lock step costs a numpy call per column of a band, so bands are large
ALIAS_BAND_TEXELS = 1 << 22


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


def _cdf(weights: np.ndarray, total: np.ndarray | None = None) -> np.ndarray:
    """(R, N) weights -> (R, N + 1) cumulative distributions from 0 to 1 (uniform for a row of zeros), float64."""
    w = np.asarray(weights, np.float64)
    c = np.empty((w.shape[0], w.shape[1] + 1))
    c[:, 0] = 0.0
    np.cumsum(w, axis=1, out=c[:, 1:])
    total = c[:, -1:].copy() if total is None else total.reshape(-1, 1)
    empty = total[:, 0] <= 0
    c /= np.where(empty[:, None], 1.0, total)
    if np.any(empty):
        c[empty] = np.linspace(0.0, 1.0, w.shape[1] + 1)
    c[:, -1] = 1.0
    return c


class LuminanceRows(Protocol):
    """What the tables are built from: an (H, W) luminance map, read a band of rows at a time (a numpy array is
    one; lights/environment.py passes the stored texels' own luminance, so the tables sample what is stored)."""

    @property
    def shape(self) -> tuple[int, ...]: ...

    def __getitem__(self, rows: slice, /) -> np.ndarray: ...


def table_floats(height: int, width: int, kind: str) -> int:
    """The length of the flat table of an H x W map (layout in build_table)."""
    if kind == "alias":
        return 2 * height + 2 * height * width
    if kind == "cdf":
        return height + 1 + height * (width + 1)
    raise ValueError(f"environment table kind must be one of {TABLE_KINDS}, got {kind!r}")


def fill_table(luminance: LuminanceRows, kind: str, out: np.ndarray, solid: np.ndarray | None = None) -> float:
    """Write the table of an (H, W) luminance map into `out` (float32, table_floats long; layout in build_table)
    and return the sum of luminance x solid angle over the texels (float64). `solid` is each row's solid angle per
    entry (H,), the texels' rows of an H x W map unless given (a Linear map's dual cells give theirs).

    The rows are read in bands of about CHUNK_TEXELS texels and only a band is ever in float64, so a 16384 x 8192
    map's cdf costs its float32 output and some 100 MB more (the alias tables are built in lock step over the rows
    of a band; maps above ALIAS_MAX_TEXELS get the cdf, lights/environment.py)."""
    h, w = luminance.shape
    if out.dtype != np.float32 or out.shape != (table_floats(h, w, kind),):
        raise ValueError(f"out must be float32 of {table_floats(h, w, kind)} entries")
    band = max(1, CHUNK_TEXELS // w)
    solid = row_solid_angles(h, w) if solid is None else np.asarray(solid, np.float64)
    rows = np.empty(h)
    if kind == "alias":
        pairs = out.reshape(-1, 2)
        cond = pairs[h:].reshape(h, w, 2)
        band = max(1, ALIAS_BAND_TEXELS // w)  # lock step: fewer, larger bands are faster
    else:
        cond = out[h + 1:].reshape(h, w + 1)
    for a in range(0, h, band):
        b = min(a + band, h)
        weights = np.asarray(luminance[a:b], np.float64) * solid[a:b, None]
        rows[a:b] = weights.sum(axis=1)
        if kind == "alias":
            cp, ca = alias_rows(weights)
            cond[a:b, :, 0] = cp
            cond[a:b, :, 1] = ca.astype(np.int32).view(np.float32)
        else:
            cond[a:b] = _cdf(weights, rows[a:b])
    if kind == "alias":
        mp, ma = alias_rows(rows[None, :])
        pairs[:h, 0] = mp[0]
        pairs[:h, 1] = ma[0].astype(np.int32).view(np.float32)
    else:
        out[:h + 1] = _cdf(rows[None, :])[0]
    return float(rows.sum())


def build_table(luminance: LuminanceRows, kind: str) -> np.ndarray:
    """The flat float32 table of an (H, W) luminance map (layout in opencl/lights/environment.h):
    alias: H (prob, alias bits) pairs of the rows, then H x W pairs of the rows' columns;
    cdf: H + 1 entries of the rows' cumulative distribution, then H rows of W + 1 of the columns'."""
    h, w = luminance.shape
    out = np.empty(table_floats(h, w, kind), np.float32)
    fill_table(luminance, kind, out)
    return out


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
