"""The Glass BSDF (opencl/bsdf/closures/glass.h): a dielectric interface of IOR `ior` that reflects and refracts
(GGX, Cycles 4.x/5.x), both tinted by Color `albedo`; `roughness` 0 is smooth glass; a Thin Film
(`thin_film_thickness`, `thin_film_ior`) colours what it reflects and, through 1 - F, what it transmits."""

from __future__ import annotations

from .kind import ClosureInputs, ClosureKind


def has_lobe(_c: ClosureInputs) -> bool:
    return True


KIND = ClosureKind("glass", code=4, fields=("albedo", "roughness", "ior", "distribution", "normal",
                                           "thin_film_thickness", "thin_film_ior"),
                   lobes=("microfacet_dielectric",), has_lobe=has_lobe, transmits=has_lobe)
