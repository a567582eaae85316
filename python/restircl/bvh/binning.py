"""Binned SAH over many nodes at once: the centroids of every node's triangles binned along an axis, and the
surface area heuristic swept over the planes between the bins, for all nodes of a level by the same array operations
(bvh/build.py)."""

from __future__ import annotations

import numpy as np


def _prefix(x: np.ndarray, op) -> np.ndarray:
    """Running op over the rows of x (row by row: numpy's accumulate along axis 0 is strided and slow)."""
    out = np.empty_like(x)
    out[0] = x[0]
    for i in range(1, len(x)):
        op(out[i - 1], x[i], out=out[i])
    return out


def _suffix(x: np.ndarray, op) -> np.ndarray:
    out = np.empty_like(x)
    out[-1] = x[-1]
    for i in range(len(x) - 2, -1, -1):
        op(out[i + 1], x[i], out=out[i])
    return out


def bin_sah(axis, single, ext, c_lo, ce_ax, lo_ax, hi_ax, seg, seg_count, S, rows, bins):
    """Bin every segment's centroids along `axis` (per segment; `single`: the same axis for all) and sweep the
    SAH over the bins - 1 planes. Returns, per segment, the best plane, its cost, the left count and the
    children's boxes (lo, hi: (S, 3) for left and right), and the bin of every triangle."""
    e_ax = ext[rows, axis].astype(np.float64)
    scale = np.where(e_ax > 0, bins * (1.0 - 1e-6) / np.where(e_ax > 0, e_ax, 1.0), 0.0).astype(np.float32)
    lo_sel = c_lo[rows, axis]
    c_sel = ce_ax[single] if single is not None else np.choose(axis[seg], ce_ax)
    bk = ((c_sel - lo_sel[seg]) * scale[seg]).astype(np.int32)
    np.clip(bk, 0, bins - 1, out=bk)
    # Per (bin, segment): triangle count and box; bin-major, so that the sweeps run over contiguous rows.
    nb = S * bins
    key = bk * np.int32(S) + seg
    cnt = np.bincount(key, minlength=nb).reshape(bins, S)
    nl = np.cumsum(cnt[:-1], axis=0, dtype=np.int64)
    nr = seg_count[None, :] - nl
    pre_lo, pre_hi, suf_lo, suf_hi = [], [], [], []
    for j in range(3):
        t = np.full(nb, np.inf, np.float32)
        np.minimum.at(t, key, lo_ax[j])
        t = t.reshape(bins, S)
        u = np.full(nb, -np.inf, np.float32)
        np.maximum.at(u, key, hi_ax[j])
        u = u.reshape(bins, S)
        pre_lo.append(_prefix(t, np.minimum))
        pre_hi.append(_prefix(u, np.maximum))
        suf_lo.append(_suffix(t, np.minimum))
        suf_hi.append(_suffix(u, np.maximum))
    with np.errstate(invalid="ignore", over="ignore"):
        dl = [pre_hi[j][:-1] - pre_lo[j][:-1] for j in range(3)]
        dr = [suf_hi[j][1:] - suf_lo[j][1:] for j in range(3)]
        al = dl[0] * dl[1] + dl[1] * dl[2] + dl[2] * dl[0]
        ar = dr[0] * dr[1] + dr[1] * dr[2] + dr[2] * dr[0]
        costs = al * nl + ar * nr
    costs[(nl == 0) | (nr == 0)] = np.inf
    plane = np.argmin(costs, axis=0)
    pr = np.minimum(plane + 1, bins - 1)
    boxes = tuple(np.stack([a[j][p, rows] for j in range(3)], 1)
                  for a, p in ((pre_lo, plane), (pre_hi, plane), (suf_lo, pr), (suf_hi, pr)))
    return plane, costs[plane, rows], nl[np.minimum(plane, bins - 2), rows], boxes, bk
