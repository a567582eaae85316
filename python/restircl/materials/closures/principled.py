"""The Principled BSDF (opencl/bsdf/closures/principled.h): Lambertian diffuse of Base Color `albedo` under a GGX
specular layer, Cycles' model without coat, sheen, subsurface and transmission. `specular` is the Specular IOR
Level: 0 has no specular layer, so the default Material is a plain diffuse albedo."""

from __future__ import annotations

from ..textures import constant_float, is_texture
from .kind import ClosureInputs, ClosureKind


def has_lobe(c: ClosureInputs) -> bool:
    """A metallic part or a specular layer (Metallic or Specular IOR Level > 0); a textured one counts as one."""
    if is_texture(c.metallic) or is_texture(c.specular):
        return True
    return constant_float(c.metallic) > 0 or constant_float(c.specular) > 0


KIND = ClosureKind("principled", code=0,
                   fields=("albedo", "metallic", "roughness", "ior", "specular", "specular_tint", "distribution",
                           "normal"),
                   lobes=("microfacet_reflection",), has_lobe=has_lobe)
