"""Packing the lanes of the 64-byte Light record (opencl/types.h): the type code in p.w and the flags in L.w as int
bits, the radiance in L.xyz, the rest as each type's module names them (mirroring opencl/lights/<type>.h)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

LANES = 16
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])

#: LIGHT_FLAG_TWO_SIDED (opencl/codes.h): an area emitter that emits on both sides
FLAG_TWO_SIDED = 1
#: LIGHT_FLAG_TEXTURED (opencl/codes.h): an emissive triangle whose radiance is read from its image at the point
#: (lights/textured_emission.py, opencl/lights/textured_emission.h)
FLAG_TEXTURED = 32

Vec = np.ndarray | Sequence[float] | float


def lanes(code: int, *, p: Vec = 0.0, a: Vec = 0.0, a_w: Vec = 0.0, b: Vec = 0.0, b_w: Vec = 0.0,
          radiance: Vec = 0.0, flags: int = 0, count: int | None = None) -> np.ndarray:
    """Records of one type: (16,) float32 for one light, or (count, 16) where the fields are per-light arrays.
    p, a, b and radiance fill xyz of their float4, a_w and b_w the w lanes. Values are rounded to float32 once, here
    (the host computes in float64)."""
    rec = np.zeros((1 if count is None else count, LANES), np.float32)
    rec[:, 0:3] = p
    rec[:, 4:7] = a
    rec[:, 7] = a_w
    rec[:, 8:11] = b
    rec[:, 11] = b_w
    rec[:, 12:15] = radiance
    rec[:, 3] = np.int32(code).view(np.float32)
    rec[:, 15] = np.int32(flags).view(np.float32)
    return rec[0] if count is None else rec


def unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v)
    return v / n if n > 0 else v
