"""The sampling tables of a world read with Linear interpolation (Environment.interpolation, opencl/lights/
environment.h environment_lookup).

Between texel centres the device blends the four nearest texels, so the radiance inside texel (i, j) comes from its
3 x 3 neighbourhood (wrapped across the seam and over the poles, as the lookup wraps). A table that drew texels by
their own luminance would never draw a black texel beside a bright one, yet light comes from it: a bias. The tables
draw each texel by what the blend integrates to over it instead: per axis, a half-texel on either side of the centre
mixes the neighbour by a quarter on average, so the neighbours weigh 1/8 each and the texel itself 3/4. Positive
wherever any of the nine is, and the cell's own integral of the blended luminance, the density the lookup wants."""

from __future__ import annotations

import numpy as np

from .table import LuminanceRows

#: the weights of the previous, own and next texel (per axis) in the blend's integral over a texel
CELL_WEIGHTS = (0.125, 0.75, 0.125)


def cell_integrals(luminance: np.ndarray, row_above: np.ndarray, row_below: np.ndarray) -> np.ndarray:
    """(R, W) float64 integrals of the blended luminance over rows of texels, given the R rows, the row above the
    first and the row below the last (wrapped by the caller); columns wrap."""
    lum = np.asarray(luminance, np.float64)
    stack = np.concatenate([np.asarray(row_above, np.float64)[None], lum, np.asarray(row_below, np.float64)[None]])
    a, b, c = CELL_WEIGHTS
    across = a * np.roll(stack, 1, axis=1) + b * stack + c * np.roll(stack, -1, axis=1)
    return a * across[:-2] + b * across[1:-1] + c * across[2:]


class LinearLuminance:
    """A LuminanceRows of the cell integrals of `source` (a LuminanceRows of the texels' luminance), a band of rows
    at a time: each band reads the row above and below it too, wrapped over the poles."""

    def __init__(self, source: LuminanceRows) -> None:
        self.source = source
        self.shape = tuple(source.shape)

    def __getitem__(self, rows: slice) -> np.ndarray:
        h = self.shape[0]
        a, b, _ = rows.indices(h)
        band = np.asarray(self.source[a:b], np.float64)
        above = np.asarray(self.source[(a - 1) % h : (a - 1) % h + 1], np.float64)[0]
        below = np.asarray(self.source[b % h : b % h + 1], np.float64)[0]
        return cell_integrals(band, above, below)
