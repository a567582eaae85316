"""What the host knows of a closure kind: the facts that validation, packing and the feature flags read."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..material import Material


@dataclass(frozen=True)
class ClosureKind:
    name: str  # Material.kind
    code: int  # CLOSURE_<NAME> in opencl/types.h; the device resolve is <name>_resolve in opencl/bsdf/closures/<name>.h
    # The Material fields its resolve reads: each is validated by its rule (materials/check.py FIELD_RULES) and
    # packed into its lanes of the Closure record (upload/materials.py FIELD_LANES); a kind ignores the others.
    fields: tuple[str, ...]
    # The lobe kinds (opencl/bsdf/<lobe>.h, registered in opencl/bsdf/lobes.h) its resolve may give a pixel
    # beyond the Lambert part
    lobes: tuple[str, ...]
    # Whether closure c (a Material of this kind) gives a lobe: a scene with one builds with HAS_GLOSSY
    has_lobe: Callable[[Material], bool]
