"""The environment's texels as the device stores them (opencl/lights/environment.h): RGB half floats or float32,
written band by band into the light buffer's array, with NaN, Inf and negative texels zeroed and counted on the
way (environment/image.py's rule; the source image is never changed).

Half floats (`vload_half3`, core OpenCL 1.2) halve the map's 12 bytes per texel. Their 11-bit mantissa rounds a
texel by at most 2^-11 of itself (docs/design.md, "The environment light": the error it adds on the `sky` scene),
but their range is 6.1e-5..65504. So the texels are stored divided by a power of two `scale` that brings the
brightest to at most 2^15 (the record's radiance multiplies it back: no texel becomes Inf, however bright), and
`auto` keeps float32 where even then some nonzero texel would fall below half's smallest normal number (a map of
more than 2^29 between its brightest and its dimmest nonzero channel)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .image import environment_rgb
from .world import Environment

TEXEL_FORMATS = ("auto", "half", "float")
#: the brightest texel is stored at most this high: 2^15, below half's largest finite 65504 after rounding
HALF_TOP = 2.0 ** 15
#: half's smallest normal number: below it the relative rounding error grows
HALF_NORMAL_MIN = 2.0 ** -14
#: texels per band while packing (the source is read a band of rows at a time)
BAND_TEXELS = 1 << 21


@dataclass
class MapStats:
    height: int
    width: int
    zeroed: int  # texels with a NaN, Inf or negative channel: stored as black
    top: float  # the largest channel of the clean texels (0 for an all-black map)
    bottom: float  # the smallest nonzero channel of the clean texels (inf for an all-black map)


def _bands(height: int, width: int):
    step = max(1, BAND_TEXELS // max(width, 1))
    for a in range(0, height, step):
        yield a, min(a + step, height)


def _clean(band: np.ndarray) -> tuple[np.ndarray, int]:
    """A band of texels as float32 with bad texels zeroed (a copy only where there are some), and their count."""
    rgb = np.asarray(band, np.float32)
    bad = ~np.all(np.isfinite(rgb) & (rgb >= 0), axis=-1)
    count = int(np.count_nonzero(bad))
    if count:
        rgb = rgb.copy()
        rgb[bad] = 0.0
    return rgb, count


def map_stats(rgb: np.ndarray) -> MapStats:
    """One pass over an (H, W, 3) map, band by band."""
    h, w = rgb.shape[:2]
    zeroed, top, bottom = 0, 0.0, math.inf
    for a, b in _bands(h, w):
        band, bad = _clean(rgb[a:b])
        zeroed += bad
        if band.size:
            top = max(top, float(band.max()))
            pos = band[band > 0]
            if pos.size:
                bottom = min(bottom, float(pos.min()))
    return MapStats(h, w, zeroed, top, bottom)


def choose_format(stats: MapStats, texel_format: str) -> str:
    """'half' or 'float' for a map: `auto` takes half unless its range needs float32 (module docstring)."""
    if texel_format not in TEXEL_FORMATS:
        raise ValueError(f"environment texel format must be one of {TEXEL_FORMATS}, got {texel_format!r}")
    if texel_format != "auto":
        return texel_format
    if stats.top <= 0:
        return "half"
    return "half" if stats.bottom / half_scale(stats.top) >= HALF_NORMAL_MIN else "float"


def half_scale(top: float) -> float:
    """The power of two the texels are divided by in half format: the brightest lands in (2^14, 2^15]."""
    if not top > 0:
        return 1.0
    return 2.0 ** (math.ceil(math.log2(top)) - 15)


def texel_floats(height: int, width: int, fmt: str) -> int:
    """float32 slots the stored texels take (half: two halves a slot, rounded up)."""
    n = 3 * height * width
    return (n + 1) // 2 if fmt == "half" else n


@dataclass
class StoredTexels:
    """The texels in `out` (a float32 array of texel_floats): how to read them back, and what it took."""

    out: np.ndarray
    height: int
    width: int
    fmt: str  # "half" or "float"
    scale: float  # stored texel x scale = radiance per unit strength
    zeroed: int

    def rows(self, a: int, b: int) -> np.ndarray:
        """(b - a, W, 3) float32 texels of rows a..b as stored (not multiplied by scale)."""
        w = self.width
        if self.fmt == "half":
            halves = self.out.view(np.float16)[: 3 * self.height * w]
            return halves[3 * a * w: 3 * b * w].astype(np.float32).reshape(b - a, w, 3)
        return self.out[3 * a * w: 3 * b * w].reshape(b - a, w, 3)

    def texels(self) -> np.ndarray:
        """(H, W, 3) float32 radiance per unit strength, as the device reads it (for tests and tools)."""
        return self.rows(0, self.height) * np.float32(self.scale)


class StoredLuminance:
    """The luminance of stored texels, a band of rows at a time (environment_table.LuminanceRows): the tables are
    built from what the device reads, so that the alias tables' pdf (luminance x norm) is what they draw."""

    def __init__(self, stored: StoredTexels, weights: np.ndarray) -> None:
        self.stored = stored
        self.weights = np.asarray(weights, np.float64)
        self.shape = (stored.height, stored.width)

    def __getitem__(self, rows: slice) -> np.ndarray:
        a, b, _ = rows.indices(self.stored.height)
        return self.stored.rows(a, b).astype(np.float64) @ self.weights


def map_source(env: Environment) -> np.ndarray:
    """(H, W, 3) float32 texels of the world before cleaning (the image, a file's pixels, or the colour as 1x1)."""
    if env.image is None and env.path is None:
        return np.asarray(env.color, np.float32).reshape(1, 1, 3)
    return environment_rgb(env)


def store_texels(rgb: np.ndarray, stats: MapStats, fmt: str, out: np.ndarray) -> StoredTexels:
    """Write the cleaned texels of `rgb` into `out` (float32, texel_floats long) in format `fmt`."""
    h, w = stats.height, stats.width
    scale = half_scale(stats.top) if fmt == "half" else 1.0
    if fmt == "half":
        if 3 * h * w % 2:
            out[-1] = 0.0  # the unused half of the last slot
        dst = out.view(np.float16)[: 3 * h * w]
    else:
        dst = out
    inv = np.float32(1.0 / scale)
    for a, b in _bands(h, w):
        band, _ = _clean(rgb[a:b])
        part = band.reshape(-1) * inv if scale != 1.0 else band.reshape(-1)
        dst[3 * a * w: 3 * b * w] = part  # float16 rounds to nearest; |part| <= 2^15 never overflows
    return StoredTexels(out, h, w, fmt, scale, stats.zeroed)
