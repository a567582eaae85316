"""Lights on the host: one module per device light type (its LightType: code, feature flag, tree bounds, area-sampling
rule, closed form, and for scene lights its packer, power and whether it has a shape; the device side is
opencl/lights/<type>.h), the registry of them all, which every other module reads the types' facts through, and the
packing of a scene's lights into device records.

A new type adds its module here and its line in registry.py; opencl/lights/<type>.h, its include and cases in
opencl/lights/lights.h are its device half; tests/lights/test_types.py checks
each fact of it by name."""

from .device_lights import DeviceLights, scene_lights
from .light_type import LightType, PlacedLight, SceneLightType
from .record import FLAG_TWO_SIDED, LUMINANCE
from .registry import FEATURE_FLAGS, SCENE_LIGHT_TYPES, TYPE_NAMES, TYPES, type_of
from .sphere import FLAG_SOFT_FALLOFF

__all__ = [
    "FEATURE_FLAGS", "FLAG_SOFT_FALLOFF", "FLAG_TWO_SIDED", "LUMINANCE", "SCENE_LIGHT_TYPES", "TYPES", "TYPE_NAMES",
    "DeviceLights", "LightType", "PlacedLight", "SceneLightType", "scene_lights", "type_of",
]
