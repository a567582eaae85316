"""What the host knows of a device light type: its code and feature flag, and every fact of it that host code needs,
each read through the registry (registry.py) so that no module keeps its own list of types:

- `bounds`: the light tree's box and cone of its records (tree.py), or DISTANT (bounds.py);
- `solid_angle`: which of its records the setting `area_sampling` may flag for solid-angle sampling
  (area_sampling.py), or `no_solid_angle`;
- `analytic`: the closed form of its direct light, the stress suite's reference (eval/stress/references.py), or
  `no_closed_form`;
- for the types made from scene lights, which scene lights it takes, how it packs one into a record, its power and
  whether it has a shape that rays meet (the camera sees it: camera_visible.py).

Every field is required: a type cannot leave one out by accident, only say what it lacks (DISTANT, no_solid_angle,
no_closed_form). The device half of each type is opencl/lights/<name>.h, dispatched from opencl/lights/lights.h."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..scene.light import Light
from .bounds import Bounds, Distant


@dataclass(frozen=True)
class PlacedLight:
    """A scene light at one frame: what a type's packer and power read."""

    light: Light
    matrix: np.ndarray  # (4, 4) object-to-world at the frame; the light points along its local -Z
    rgb_power: np.ndarray  # (3,) float64: colour * power at the frame (W; W/m^2 for the sun)
    scene_radius: float  # half the diagonal of the scene's bounds


class NotAnalytic(ValueError):
    """A light's closed form does not cover this case (a type without one, or a light across a point's horizon)."""


#: (lanes (k, 16) float64, flags (k,) int32) of k records of the type -> their Bounds
BoundsRule = Callable[[np.ndarray, np.ndarray], Bounds]
#: (lanes, flags) -> (k,) bool: the records the type's sampler can draw uniformly in solid angle
SolidAngleRule = Callable[[np.ndarray, np.ndarray], np.ndarray]
#: (x (P, 3), unit normals (P, 3), lanes (S, 16) float64, flags (S,) int32) -> (P, S) float64: the unshadowed
#: direct light of each record at each point per unit of its radiance lanes (L.xyz), i.e. the projected solid angle
#: it covers, or cos / d^2 for a point; raises NotAnalytic where it has no closed form
AnalyticRule = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray], np.ndarray]


def no_solid_angle(lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """SolidAngleRule of a type sampled in its own measure whatever `area_sampling` says (the sun, the
    environment)."""
    return np.zeros(len(lanes), bool)


class NoClosedForm:
    """AnalyticRule of a type without a closed form here (`no_closed_form`): the stress suite compares its cases with
    another reference."""

    def __init__(self, what: str):
        self.what = what

    def __call__(self, x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
        raise NotAnalytic(f"{self.what} have no analytic reference here")


def no_closed_form(what: str) -> NoClosedForm:
    """The AnalyticRule of a type without one; `what` names its lights in the message ("disk lights")."""
    return NoClosedForm(what)


@dataclass(frozen=True)
class LightType:
    name: str
    code: int  # LIGHT_<NAME> in opencl/lights/<name>.h
    flag: str  # HAS_<NAME>_LIGHTS: compiles the type's code in (render/features.py)
    bounds: BoundsRule | Distant  # the light tree's bounds of its records, or DISTANT: not in the tree
    solid_angle: SolidAngleRule  # area_sampling.py
    analytic: AnalyticRule  # eval/stress/references.py


@dataclass(frozen=True)
class SceneLightType(LightType):
    """A type made from the scene's lights (every type but the emissive triangles, which come from geometry, and
    the environment, which comes from the world)."""

    accepts: Callable[[Light], bool]  # the scene lights this type packs
    record: Callable[[PlacedLight], np.ndarray]  # (16,) float32 lanes of the Light record (record.lanes)
    power: Callable[[PlacedLight], float]  # coarse importance for the light array: luminance-weighted power, W
    # a ray can meet it (not a delta): camera rays test it when it is visible to the camera (camera_visible.py) and
    # the exhaustive reference is not exact (eval/stress/references.py); the device's <name>_hittable reads the
    # same from the record (tests/lights/test_types.py checks that they agree)
    has_shape: Callable[[Light], bool]
