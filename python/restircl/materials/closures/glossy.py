"""The Glossy BSDF (opencl/bsdf/closures/glossy.h): GGX reflection of colour `albedo`, no Fresnel."""

from __future__ import annotations

from .kind import ClosureInputs, ClosureKind


def has_lobe(_c: ClosureInputs) -> bool:
    return True


KIND = ClosureKind("glossy", code=2, fields=("albedo", "roughness", "distribution", "normal"),
                   lobes=("microfacet_reflection",), has_lobe=has_lobe)
