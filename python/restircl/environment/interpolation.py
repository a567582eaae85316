"""The sampling tables of a world read with Linear interpolation (Environment.interpolation, opencl/lights/
environment.h environment_lookup).

Between texel centres the device blends the four nearest texels, so the blend is one bilinear patch over each *dual
cell*, the cell between four texel centres: dual cell (k, j) lies between centre rows k - 1 and k and centre columns
j and j + 1 (all wrapped: columns across the seam, rows over the poles, as the lookup wraps). There are W dual
columns (the last one straddles the seam) and H + 1 dual rows: row 0 is the half-row above the first centre (its
patch between rows H - 1 and 0, the lower half of it) and row H the half-row below the last (the upper half of the
same patch), the others whole. The tables draw a dual cell by its patch's mean luminance x its band's solid angle;
the device then draws (u, v) inside it proportionally to the patch (environment_sample_linear), so the density
follows the blend wherever the band's sin(theta) is nearly constant."""

from __future__ import annotations

import numpy as np

from .table import LuminanceRows


def dual_row_extent(height: int) -> tuple[np.ndarray, np.ndarray]:
    """(H + 1,) each: where each dual row starts and ends in its patch's ty (0 at the upper centre row, 1 at the
    lower): [1/2, 1] for the first, [0, 1/2] for the last, [0, 1] for the others."""
    t0 = np.zeros(height + 1)
    t1 = np.ones(height + 1)
    t0[0] = 0.5
    t1[-1] = 0.5
    return t0, t1


def dual_row_solid_angles(height: int, width: int) -> np.ndarray:
    """(H + 1,) float64: the solid angle of one dual cell of each dual row (v from max(k - 1/2, 0) / H to
    min(k + 1/2, H) / H)."""
    k = np.arange(height + 1, dtype=np.float64)
    lo = np.maximum(k - 0.5, 0.0) / height
    hi = np.minimum(k + 0.5, height) / height
    return (np.cos(np.pi * lo) - np.cos(np.pi * hi)) * (2.0 * np.pi / width)


def dual_means(upper: np.ndarray, lower: np.ndarray, t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """(R, W) float64 mean luminance of the patches between centre rows `upper` and `lower` (each (R, W)), over ty in
    [t0, t1] (each (R,)) and the whole of tx; columns wrap."""
    tm = (0.5 * (np.asarray(t0) + np.asarray(t1)))[:, None]
    rows = (1.0 - tm) * np.asarray(upper, np.float64) + tm * np.asarray(lower, np.float64)
    return 0.5 * (rows + np.roll(rows, -1, axis=1))


class DualLuminance:
    """A LuminanceRows of shape (H + 1, W): the mean luminance of each dual cell of `source` (a LuminanceRows of the
    texels' luminance), a band of dual rows at a time; `row_solid` the dual rows' solid angles for fill_table."""

    def __init__(self, source: LuminanceRows) -> None:
        self.source = source
        h, w = source.shape[:2]
        self.height = h
        self.shape = (h + 1, w)
        self.row_solid = dual_row_solid_angles(h, w)
        self.t0, self.t1 = dual_row_extent(h)

    def __getitem__(self, rows: slice) -> np.ndarray:
        h = self.height
        a, b, _ = rows.indices(h + 1)
        if b <= a:
            return np.zeros((0, self.shape[1]))
        # centre rows a - 1 .. b - 1 (wrapped at both ends): the upper and lower rows of every dual row of the band
        inner = np.asarray(self.source[max(a - 1, 0) : min(b, h)], np.float64)
        parts = [np.asarray(self.source[h - 1 : h], np.float64)] if a == 0 else []
        parts.append(inner)
        if b == h + 1:
            parts.append(np.asarray(self.source[0:1], np.float64))
        centres = np.concatenate(parts)
        return dual_means(centres[:-1], centres[1:], self.t0[a:b], self.t1[a:b])
