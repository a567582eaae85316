"""Every device light type, by code: the one list that render/features.py, core/layouts.py, the packing, the light
tree (tree.py), area sampling (area_sampling.py), the camera's lights (camera_visible.py) and the stress suite's
reference (eval/stress/references.py) read. A new type is its module (lights/<name>.py: a LightType with every
fact of it), its line here, its header opencl/lights/<name>.h and its cases in opencl/lights/lights.h."""

from __future__ import annotations

import numpy as np

from ..scene.errors import SceneError
from ..scene.light import Light
from . import disk, environment, quad, sphere, spot, sun, triangle
from .light_type import LightType, SceneLightType

SCENE_LIGHT_TYPES: tuple[SceneLightType, ...] = (quad.TYPE, disk.TYPE, sphere.TYPE, spot.TYPE, sun.TYPE)
TYPES: tuple[LightType, ...] = tuple(
    sorted((triangle.TYPE, environment.TYPE, *SCENE_LIGHT_TYPES), key=lambda t: t.code))
TYPE_NAMES: dict[int, str] = {t.code: t.name for t in TYPES}
FEATURE_FLAGS: dict[int, str] = {t.code: t.flag for t in TYPES}
_BY_CODE: dict[int, LightType] = {t.code: t for t in TYPES}


def type_of(lt: Light) -> SceneLightType:
    """The device type that packs scene light `lt`."""
    for t in SCENE_LIGHT_TYPES:
        if t.accepts(lt):
            return t
    raise SceneError(f"light {lt.name!r}: no device light type for type {lt.type!r} (shape {lt.shape!r})")


def type_with_code(code: int) -> LightType:
    """The type of records with LIGHT_* code `code`; a ValueError for a code no type has (nothing would read
    such a record)."""
    try:
        return _BY_CODE[int(code)]
    except KeyError:
        raise ValueError(f"light type code {code}: no registered type (lights/registry.py)") from None


def groups(types: np.ndarray) -> list[tuple[LightType, np.ndarray | slice]]:
    """Each registered type among the LIGHT_* codes `types` (one per record) with the index of its records: a
    boolean mask, or slice(None) when every record has that type (no copy of a million lanes)."""
    types = np.asarray(types)
    codes = np.unique(types)
    if len(codes) == 1:
        return [(type_with_code(codes[0]), slice(None))]
    return [(type_with_code(c), types == c) for c in codes]
