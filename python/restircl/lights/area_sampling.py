"""Which density area lights are sampled with (setting `area_sampling`): the record flags that opencl/lights/
solid_angle.h reads. `area` samples every area light uniformly in area (as before); `solid_angle` samples
rectangles (spherical rectangles), ellipses (the spherical rectangle around them), emissive triangles (spherical
triangles) and soft-falloff point lights (the cone of their disk) uniformly in solid angle, wherever float32 allows;
`auto` does so only where the light looks large from the shading point (its bounding radius above a quarter of its
distance, SA_AUTO_RATIO), since small or far lights are sampled about as well by area and more cheaply."""

from __future__ import annotations

import numpy as np

from . import disk, quad, sphere, spot, triangle

#: LIGHT_FLAG_SOLID_ANGLE, LIGHT_FLAG_SA_AUTO (opencl/codes.h; read by opencl/lights/solid_angle.h): sample by solid
#: angle where float32 allows, else by area; ... and only where the light looks large from the shading point
FLAG_SOLID_ANGLE = 4
FLAG_SA_AUTO = 8
_MODE_FLAGS = {"area": 0, "solid_angle": FLAG_SOLID_ANGLE, "auto": FLAG_SOLID_ANGLE | FLAG_SA_AUTO}

_PLANAR_RECT = (quad.TYPE.code, disk.TYPE.code)  # sampled through a spherical rectangle: need orthogonal spans
_SPHERES = (sphere.TYPE.code, spot.TYPE.code)    # soft-falloff disks only (a sphere's cone is sampled anyway)


def sampling_flags(records: np.ndarray, types: np.ndarray, mode: str) -> np.ndarray:
    """The flag bits (int32, one per record of layouts.LIGHT) that `mode` adds to these lights."""
    if mode not in _MODE_FLAGS:
        raise ValueError(f"area_sampling {mode!r}: not one of {', '.join(_MODE_FLAGS)}")
    out = np.zeros(len(records), np.int32)
    if not _MODE_FLAGS[mode] or not len(records):
        return out
    lanes = records.view(np.float32).reshape(-1, 16).astype(np.float64)
    flags = lanes[:, 15].astype(np.float32).view(np.int32)
    a, b = lanes[:, 4:7], lanes[:, 8:11]
    la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        orthogonal = np.abs((a * b).sum(1)) <= 1e-4 * la * lb
    wants = (np.isin(types, _PLANAR_RECT) & orthogonal) | (types == triangle.TYPE.code)
    wants |= np.isin(types, _SPHERES) & ((flags & sphere.FLAG_SOFT_FALLOFF) != 0)
    out[wants] = _MODE_FLAGS[mode]
    return out


def apply_sampling_flags(records: np.ndarray, types: np.ndarray, mode: str) -> None:
    """Set `mode`'s flag bits in the flag lane (L.w) of `records`, in place."""
    lanes = records.view(np.float32).reshape(-1, 16)
    flags = lanes[:, 15].copy().view(np.int32) | sampling_flags(records, types, mode)
    lanes[:, 15] = flags.view(np.float32)
