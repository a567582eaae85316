"""The Diffuse BSDF (opencl/bsdf/closures/diffuse.h): Lambert of colour `albedo` (its Roughness, Oren-Nayar, is not
modelled)."""

from __future__ import annotations

from .kind import ClosureInputs, ClosureKind


def has_lobe(_c: ClosureInputs) -> bool:
    return False


KIND = ClosureKind("diffuse", code=1, fields=("albedo", "normal"), lobes=(), has_lobe=has_lobe)
