"""The Refraction BSDF (opencl/bsdf/closures/glass.h): GGX refraction through an interface of IOR `ior`, Color
`albedo`, without reflection and without Fresnel (Cycles: all of it refracts but what total internal reflection
keeps, which is lost)."""

from __future__ import annotations

from .kind import ClosureInputs, ClosureKind


def has_lobe(_c: ClosureInputs) -> bool:
    return True


KIND = ClosureKind("refraction", code=5, fields=("albedo", "roughness", "ior", "distribution", "normal"),
                   lobes=("microfacet_dielectric",), has_lobe=has_lobe, transmits=has_lobe)
