"""The environment light (opencl/lights/environment.h): the scene's world as one light of solid-angle measure.

Its record goes first in the light buffer (primary.cl finds what camera rays see there) and its map and sampling
table after every record, where the record's offsets point. Texels are colour x image (per unit strength), so the
tables sample the luminance of the radiance itself; the strength (animated by strength_per_frame) is the record's
radiance scale and does not rebuild them.

Power, by which the light array weighs it against the other lights (as the sun's, docs/units.md): what a disk of
the scene's radius R facing a uniform world of the map's mean radiance L receives, pi L x pi R^2."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..environment import Environment
from ..environment_image import environment_texels
from ..environment_table import build_table, texel_weights
from .light_type import LightType
from .record import LUMINANCE, lanes

TYPE = LightType("environment", code=6, flag="HAS_ENVIRONMENT")
FLAG_CAMERA = 2  # ENV_FLAG_CAMERA
FLAG_CDF = 4  # ENV_FLAG_CDF
#: the sampling table of new scenes: "alias" or "cdf" (environment_table.py; measured in docs/benchmarks.md)
TABLE_KIND = "alias"


@dataclass
class PackedMap:
    """What does not change with the strength: the texels, their sampling table and its normalisation."""

    key: tuple
    texels: np.ndarray  # (H, W, 3) float32
    table: np.ndarray  # flat float32 (environment_table.build_table)
    kind: str
    weight_sum: float  # sum of luminance x solid angle over the texels
    zeroed: int  # texels that were NaN, Inf or negative


def packed_map(env: Environment, kind: str | None = None) -> PackedMap:
    """The world's map and table, built once per image and table kind (kept on the Environment)."""
    kind = kind or TABLE_KIND
    rot = None if env.rotation is None else np.asarray(env.rotation).tobytes()
    key = (id(env.image), env.path, tuple(env.color), kind, rot)
    cached = getattr(env, "_packed_map", None)
    if cached is not None and cached.key == key:
        return cached
    texels, zeroed = environment_texels(env)
    lum = texels.astype(np.float64) @ LUMINANCE
    table = build_table(lum, kind)
    packed = PackedMap(key, texels, table, kind, float(texel_weights(lum).sum()), zeroed)
    object.__setattr__(env, "_packed_map", packed)
    return packed


def record(env: Environment, packed: PackedMap, frame: int) -> np.ndarray:
    """The (16,) float32 record; its texel and table offsets are set by place_data once the records are counted."""
    strength = env.strength_at(frame)
    rot = np.eye(3) if env.rotation is None else np.asarray(env.rotation, np.float64)
    h, w = packed.texels.shape[:2]
    norm = 1.0 / packed.weight_sum if packed.weight_sum > 0 and strength > 0 else 0.0
    flags = (FLAG_CAMERA if env.visible_camera else 0) | (FLAG_CDF if packed.kind == "cdf" else 0)
    rec = lanes(TYPE.code, a=rot[0], b=rot[1], b_w=norm, radiance=(strength,) * 3, flags=flags)
    rec[1:3] = np.array([w, h], np.int32).view(np.float32)
    return rec


def power(env: Environment, packed: PackedMap, frame: int, scene_radius: float) -> float:
    mean = packed.weight_sum / (4.0 * math.pi)
    return env.strength_at(frame) * math.pi * mean * math.pi * scene_radius * scene_radius


def data(packed: PackedMap) -> np.ndarray:
    """The floats that follow the records: the texels, then the table."""
    return np.concatenate([packed.texels.reshape(-1), packed.table])


def place_data(records: np.ndarray, index: int, packed: PackedMap) -> None:
    """Point record `index` of the (N, 16) float32 records at its data, which follows all N of them."""
    tex = (len(records) - index) * 16
    records[index, 0] = np.int32(tex).view(np.float32)
    records[index, 7] = np.int32(tex + packed.texels.size).view(np.float32)


def data_bytes(height: int, width: int, kind: str) -> int:
    """Device bytes of a map of this size (texels and table)."""
    table = 2 * height + 2 * height * width if kind == "alias" else height + 1 + height * (width + 1)
    return 4 * (3 * height * width + table)
