"""The environment light (opencl/lights/environment.h): the scene's world as one light of solid-angle measure.

Its record goes first in the light buffer (camera/primary.cl finds what camera rays see there) and its map and sampling
table after every record, where the record's offsets point. Texels are the image, or the colour without one (per
unit strength), so the tables sample the luminance of the radiance itself; the strength (animated by
strength_per_frame) is the record's radiance scale and does not rebuild them.

Power, by which the light array weighs it against the other lights (as the sun's, docs/units.md): what a disk of
the scene's radius R facing a uniform world of the map's mean radiance L receives, pi L x pi R^2."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..environment.interpolation import DualLuminance
from ..environment.pack import (
    StoredLuminance,
    StoredTexels,
    choose_format,
    map_source,
    map_stats,
    store_texels,
    texel_floats,
)
from ..environment.table import fill_table, table_floats
from ..environment.world import Environment
from .bounds import DISTANT
from .light_type import LightType, no_closed_form, no_solid_angle
from .record import LUMINANCE, lanes

TYPE = LightType("environment", code=6, flag="HAS_ENVIRONMENT",
                 bounds=DISTANT, solid_angle=no_solid_angle, analytic=no_closed_form("environments"))
#: ENV_FLAG_* (opencl/codes.h): the camera sees the world; the cdf table (else alias); half-float texels; the map is
#: read with Linear interpolation (else Closest)
FLAG_CAMERA, FLAG_CDF, FLAG_HALF, FLAG_LINEAR = 2, 4, 8, 16
#: the sampling table of new scenes: "alias" or "cdf" (environment/table.py; measured in
#: docs/measurements/benchmarks.md)
TABLE_KIND = "alias"
#: maps above this many texels get the cdf table whatever TABLE_KIND says: the host builds alias tables row by row
#: in lock step, 23 s for 4096 x 2048 against 3.3 s for the cdf (docs/measurements/benchmarks.md), minutes for 16384
#: x 8192
ALIAS_MAX_TEXELS = 1 << 22
#: how the texels are stored on the device: "auto" (half floats unless the map's range needs float32), "half" or
#: "float" (environment/pack.py; the error half floats add is measured in docs/design.md, "The environment light")
TEXEL_FORMAT = "auto"


@dataclass
class PackedMap:
    """What does not change with the strength: the texels and their sampling table, in the one float32 array that
    follows the light records on the device (`data`: the stored texels, then the table)."""

    key: tuple
    data: np.ndarray  # flat float32: texel_floats of the stored texels, then the table (table_floats)
    stored: StoredTexels  # the texels' format and scale; a view of the front of `data`
    kind: str
    weight_sum: float  # sum of luminance x solid angle over the stored texels (times stored.scale: radiance's)
    zeroed: int  # texels that were NaN, Inf or negative
    linear: bool = False  # read with Linear interpolation (Environment.interpolation), else Closest

    @property
    def shape(self) -> tuple[int, int]:
        return self.stored.height, self.stored.width

    @property
    def texel_floats(self) -> int:
        return len(self.stored.out)

    @property
    def table(self) -> np.ndarray:
        return self.data[self.texel_floats:]

    @property
    def texels(self) -> np.ndarray:
        """(H, W, 3) float32 radiance per unit strength as the device reads it (decoded: for tests and tools)."""
        return self.stored.texels()


def packed_map(env: Environment, kind: str | None = None, texel_format: str | None = None) -> PackedMap:
    """The world's map and table, built once per image, table kind and texel format (kept on the Environment; an
    image changed in place is not seen: assign a new array). Built band by band straight into `data`: besides the
    source image, a map costs its device bytes (data_bytes) and a band's worth of scratch.

    A map read with Linear interpolation samples the blend's bilinear patches between texel centres, its H + 1 rows
    of dual cells (environment/interpolation.py), with the cdf table, whose probabilities the device reads from the
    table itself (the alias tables' density is the texel's own luminance)."""
    rot = None if env.rotation is None else np.asarray(env.rotation).tobytes()
    linear = env.interpolation == "Linear"
    key = (id(env.image), env.path, tuple(env.color), kind or TABLE_KIND, texel_format or TEXEL_FORMAT, rot, linear)
    cached = getattr(env, "_packed_map", None)
    if cached is not None and cached.key == key:
        return cached
    rgb = map_source(env)
    stats = map_stats(rgb)
    if stats.zeroed:
        warnings.warn(f"world {env.name!r}: {stats.zeroed} texel(s) of its image are NaN, Inf or negative; they "
                      "are black", stacklevel=3)
    h, w = stats.height, stats.width
    fmt = choose_format(stats, texel_format or TEXEL_FORMAT)
    if linear:
        kind = "cdf"
    elif kind is None:
        kind = TABLE_KIND if h * w <= ALIAS_MAX_TEXELS else "cdf"
    n_tex = texel_floats(h, w, fmt)
    data = np.empty(n_tex + table_floats(h + 1 if linear else h, w, kind), np.float32)
    stored = store_texels(rgb, stats, fmt, data[:n_tex])
    del rgb
    luminance = StoredLuminance(stored, LUMINANCE)
    if linear:
        dual = DualLuminance(luminance)
        weight_sum = fill_table(dual, kind, data[n_tex:], dual.row_solid)
    else:
        weight_sum = fill_table(luminance, kind, data[n_tex:])
    packed = PackedMap(key, data, stored, kind, weight_sum, stats.zeroed, linear)
    object.__setattr__(env, "_packed_map", packed)
    return packed


def record(env: Environment, packed: PackedMap, frame: int) -> np.ndarray:
    """The (16,) float32 record; its texel and table offsets are set by place_data once the records are counted."""
    strength = env.strength_at(frame)
    rot = np.eye(3) if env.rotation is None else np.asarray(env.rotation, np.float64)
    h, w = packed.shape
    norm = 1.0 / packed.weight_sum if packed.weight_sum > 0 and strength > 0 else 0.0
    flags = ((FLAG_CAMERA if env.visible_camera else 0) | (FLAG_CDF if packed.kind == "cdf" else 0)
             | (FLAG_HALF if packed.stored.fmt == "half" else 0) | (FLAG_LINEAR if packed.linear else 0))
    # the stored texels are radiance / scale (a power of two): the record's radiance multiplies it back
    rec = lanes(TYPE.code, a=rot[0], b=rot[1], b_w=norm, radiance=(strength * packed.stored.scale,) * 3,
                flags=flags)
    rec[1:3] = np.array([w, h], np.int32).view(np.float32)
    return rec


def power(env: Environment, packed: PackedMap, frame: int, scene_radius: float) -> float:
    mean = packed.weight_sum * packed.stored.scale / (4.0 * math.pi)
    return env.strength_at(frame) * math.pi * mean * math.pi * scene_radius * scene_radius


def data(packed: PackedMap) -> np.ndarray:
    """The floats that follow the records: the stored texels, then the table (not a copy)."""
    return packed.data


def place_data(records: np.ndarray, index: int, packed: PackedMap) -> None:
    """Point record `index` of the (N, 16) float32 records at its data, which follows all N of them."""
    tex = (len(records) - index) * 16
    records[index, 0] = np.int32(tex).view(np.float32)
    records[index, 7] = np.int32(tex + packed.texel_floats).view(np.float32)


def data_bytes(height: int, width: int, kind: str, fmt: str = "half") -> int:
    """Device bytes of a map of this size (texels in format `fmt`, "half" or "float", and the table)."""
    return 4 * (texel_floats(height, width, fmt) + table_floats(height, width, kind))
