"""What the host knows of a closure kind: the facts that validation, packing and the feature flags read."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from ..textures import Input


class ClosureInputs(Protocol):
    """What a kind's has_lobe reads of a closure (a restircl.Material, which builds on this registry: material.py)."""

    metallic: Input
    specular: Input
    transmission: float
    thin_film_thickness: float


def never(_c: ClosureInputs) -> bool:
    return False


@dataclass(frozen=True)
class ClosureKind:
    name: str  # Material.kind
    # CLOSURE_<NAME> (opencl/codes.h, generated); its resolve: <name>_resolve, opencl/bsdf/closures/<name>.h
    code: int
    # The Material fields its resolve reads: each is validated by its rule (materials/check.py FIELD_RULES) and
    # packed into its lanes of the Closure record (upload/materials.py FIELD_LANES); a kind ignores the others.
    fields: tuple[str, ...]
    # The lobe kinds (opencl/bsdf/<lobe>.h, registered in opencl/bsdf/lobes.h) its resolve may give a pixel
    # beyond the Lambert part
    lobes: tuple[str, ...]
    # Whether closure c (a Material of this kind) gives a lobe: a scene with one builds with HAS_GLOSSY
    has_lobe: Callable[[ClosureInputs], bool]
    # Whether closure c refracts (a dielectric lobe, opencl/bsdf/microfacet_dielectric.h): a scene with one builds
    # with HAS_TRANSMISSION
    transmits: Callable[[ClosureInputs], bool] = never
