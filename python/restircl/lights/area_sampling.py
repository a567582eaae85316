"""Which density area lights are sampled with (setting `area_sampling`): the record flags that opencl/lights/
solid_angle.h reads. The lights whose type can do it (LightType.solid_angle: rectangles by spherical rectangles,
ellipses by the spherical rectangle around them, emissive triangles by spherical triangles, soft-falloff point
lights by the cone of their disk) are sampled uniformly in solid angle, wherever float32 allows: `solid_angle`
everywhere; `auto` only where the light looks large from the shading point (its bounding radius above a quarter of
its distance, SA_AUTO_RATIO), since small or far lights are sampled about as well by area and more cheaply; `area`
only within twice the light's bounding radius of its centre (SA_NEAR_RATIO), uniformly in area beyond. No mode
samples a light uniformly in area right next to the shading point: there the target's 1 / d^2 is not in the area
density, the weight target / pdf grows without bound as the shading point nears the light, and a receiver touching
an emitter gets an estimator of infinite variance (fireflies that never average out; docs/design.md, "Many
lights")."""

from __future__ import annotations

import numpy as np

from .registry import groups

#: LIGHT_FLAG_SOLID_ANGLE, LIGHT_FLAG_SA_AUTO, LIGHT_FLAG_SA_NEAR (opencl/codes.h; read by opencl/lights/
#: solid_angle.h): sample by solid angle where float32 allows, else by area; ... and only where the light looks large
#: from the shading point; ... and only where the shading point is near the light
FLAG_SOLID_ANGLE = 4
FLAG_SA_AUTO = 8
FLAG_SA_NEAR = 16
_MODE_FLAGS = {"area": FLAG_SOLID_ANGLE | FLAG_SA_NEAR, "solid_angle": FLAG_SOLID_ANGLE,
               "auto": FLAG_SOLID_ANGLE | FLAG_SA_AUTO}


def sampling_flags(records: np.ndarray, types: np.ndarray, mode: str) -> np.ndarray:
    """The flag bits (int32, one per record of layouts.LIGHT) that `mode` adds to these lights: to the records each
    type's rule (LightType.solid_angle, lights/<type>.py) says it can sample by solid angle."""
    if mode not in _MODE_FLAGS:
        raise ValueError(f"area_sampling {mode!r}: not one of {', '.join(_MODE_FLAGS)}")
    out = np.zeros(len(records), np.int32)
    if not len(records):
        return out
    lanes = records.view(np.float32).reshape(-1, 16).astype(np.float64)
    flags = records.view(np.int32).reshape(-1, 16)[:, 15]
    wants = np.zeros(len(records), bool)
    for t, sel in groups(types):
        wants[sel] = t.solid_angle(lanes[sel], flags[sel])
    out[wants] = _MODE_FLAGS[mode]
    return out


def apply_sampling_flags(records: np.ndarray, types: np.ndarray, mode: str) -> None:
    """Set `mode`'s flag bits in the flag lane (L.w) of `records`, in place."""
    lanes = records.view(np.float32).reshape(-1, 16)
    flags = lanes[:, 15].copy().view(np.int32) | sampling_flags(records, types, mode)
    lanes[:, 15] = flags.view(np.float32)
