"""Every device light type, by code: the one list render/features.py, core/layouts.py and the packing read."""

from __future__ import annotations

from ..scene.errors import SceneError
from ..scene.light import Light
from . import disk, environment, quad, sphere, spot, sun, triangle
from .light_type import LightType, SceneLightType

SCENE_LIGHT_TYPES: tuple[SceneLightType, ...] = (quad.TYPE, disk.TYPE, sphere.TYPE, spot.TYPE, sun.TYPE)
TYPES: tuple[LightType, ...] = tuple(
    sorted((triangle.TYPE, environment.TYPE, *SCENE_LIGHT_TYPES), key=lambda t: t.code))
TYPE_NAMES: dict[int, str] = {t.code: t.name for t in TYPES}
FEATURE_FLAGS: dict[int, str] = {t.code: t.flag for t in TYPES}


def type_of(lt: Light) -> SceneLightType:
    """The device type that packs scene light `lt`."""
    for t in SCENE_LIGHT_TYPES:
        if t.accepts(lt):
            return t
    raise SceneError(f"light {lt.name!r}: no device light type for type {lt.type!r} (shape {lt.shape!r})")
