"""The Principled BSDF (opencl/bsdf/closures/principled.h): Lambertian diffuse of Base Color `albedo` under a GGX
specular layer, Cycles' model without coat, sheen and subsurface; `transmission` (the Transmission Weight) makes
that share of the dielectric part glass (opencl/bsdf/closures/glass.h), or with `thin_wall` a thin sheet
(opencl/bsdf/closures/thin_wall.h). `specular` is the Specular IOR Level: 0 has no specular layer, so the default
Material is a plain diffuse albedo."""

from __future__ import annotations

from ..textures import constant_float, is_texture
from ..thin_film import has_film
from .kind import ClosureInputs, ClosureKind


def transmits(c: ClosureInputs) -> bool:
    """A Transmission Weight > 0 (unless it is all metal)."""
    return float(c.transmission) > 0 and (is_texture(c.metallic) or constant_float(c.metallic) < 1)


def has_lobe(c: ClosureInputs) -> bool:
    """A metallic part, a specular layer or glass (Metallic, Specular IOR Level or Transmission Weight > 0), or a
    thin film (which reflects even without a specular layer, as in Cycles); a textured one counts as one."""
    if is_texture(c.metallic) or is_texture(c.specular) or transmits(c) or has_film(c):
        return True
    return constant_float(c.metallic) > 0 or constant_float(c.specular) > 0


KIND = ClosureKind("principled", code=0,
                   fields=("albedo", "metallic", "roughness", "ior", "specular", "specular_tint", "distribution",
                           "normal", "transmission", "thin_wall", "thin_film_thickness", "thin_film_ior"),
                   lobes=("microfacet_reflection", "microfacet_dielectric", "thin_dielectric", "thin_film_reflection"),
                   has_lobe=has_lobe,
                   transmits=transmits)
