"""Every closure kind, by code: the one list that validation, packing, the feature flags and the kind codes
(upload/materials.py KIND_CODE) read. A new kind is its module and its line here, plus its device resolve."""

from __future__ import annotations

from . import diffuse, glass, glossy, principled, refraction
from .kind import ClosureKind

CLOSURE_KINDS: tuple[ClosureKind, ...] = tuple(sorted((principled.KIND, diffuse.KIND, glossy.KIND, glass.KIND,
                                                       refraction.KIND),
                                                      key=lambda k: k.code))
KINDS: dict[str, ClosureKind] = {k.name: k for k in CLOSURE_KINDS}


def kind_of(name: str) -> ClosureKind:
    """The kind of Material.kind `name` (materials/check.py rejects the others first, naming the material)."""
    if name not in KINDS:
        raise ValueError(f"no closure kind {name!r}: one of {tuple(KINDS)}")
    return KINDS[name]
