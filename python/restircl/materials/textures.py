"""Texture nodes that feed a material input (restircl.Material): an image, a checker, a colour mix, a normal map,
and the converter nodes of PBR graphs (Separate / Combine Color, Math, Vector Math, Invert, Hue/Saturation/Value,
Color Ramp, RGB Curves), and the mesh's colour attributes (Color Attribute, Attribute).

A material input (base colour, roughness, metallic, ...) is a constant or one of these nodes; a node's own inputs
may again be nodes (a Mix Color of an image and a checker), as in a Blender node graph. Texture coordinates follow
Blender's Texture Coordinate node: "uv" (the mesh's UV map, Mesh.uvs), "generated" (the object's bounding box
mapped to [0, 1]^3) and "object" (object-space position). `mapping` is an optional 4x4 matrix applied to the
coordinate first (Blender's Mapping node, type Point).

The renderer evaluates these on the device at the primary hit (opencl/texture*.h); images live in one buffer with
an offset table and a mip chain (python/restircl/upload/textures.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Union

import numpy as np

COORDS = ("uv", "generated", "object")
INTERPOLATIONS = ("Linear", "Closest")
EXTENSIONS = ("REPEAT", "EXTEND", "CLIP")
# the first nine keep their device codes; the rest are the other blend modes Cycles has
MIX_BLENDS = ("MIX", "MULTIPLY", "ADD", "SUBTRACT", "SCREEN", "DIFFERENCE", "DARKEN", "LIGHTEN", "OVERLAY", "BURN",
              "DODGE", "DIVIDE", "SOFT_LIGHT", "LINEAR_LIGHT", "EXCLUSION", "HUE", "SATURATION", "VALUE", "COLOR")
COLOR_MODES = ("RGB", "HSV", "HSL")  # Separate / Combine Color
# Blender's Math node operations read natively (the node's `operation` names)
MATH_OPS = ("ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "POWER", "LOGARITHM", "SQRT", "INVERSE_SQRT",
            "ABSOLUTE", "EXPONENT", "MINIMUM", "MAXIMUM", "LESS_THAN", "GREATER_THAN", "SIGN", "COMPARE", "ROUND",
            "FLOOR", "CEIL", "TRUNC", "FRACT", "MODULO", "FLOORED_MODULO", "SNAP", "SINE", "COSINE", "TANGENT",
            "ARCTAN2", "RADIANS", "DEGREES")
# Vector Math operations read natively; the last three give a number (the node's Value output)
VECTOR_OPS = ("ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "SCALE", "ABSOLUTE", "MINIMUM", "MAXIMUM", "FLOOR", "CEIL",
              "FRACTION", "NORMALIZE", "CROSS_PRODUCT", "DOT_PRODUCT", "LENGTH", "DISTANCE")
VECTOR_VALUE_OPS = ("DOT_PRODUCT", "LENGTH", "DISTANCE")
RAMP_INTERPOLATIONS = ("LINEAR", "CONSTANT", "EASE")  # Color Ramp interpolations read natively
ATTRIBUTE_OUTPUTS = ("color", "alpha", "fac")  # the outputs of Attribute


@dataclass
class ImageTexture:
    """Blender's Image Texture node. `image`: an (H, W) / (H, W, 1..4) array (uint8, uint16 or float; float is taken
    as stored, integers as value / max) or a path to a PNG/JPEG/EXR/HDR file, read at upload. sRGB images are
    decoded to linear on upload. `alpha`: the node's Alpha output (a number: the image's alpha channel, 1 where it
    has none) instead of Color."""

    image: np.ndarray | str | Path
    colorspace: str = "sRGB"
    interpolation: str = "Linear"
    extension: str = "REPEAT"
    coords: str = "uv"
    mapping: np.ndarray | None = None
    name: str = ""
    alpha: bool = False


@dataclass
class CheckerTexture:
    """Blender's Checker Texture: color1 where floor(s x) + floor(s y) + floor(s z) is even... as Blender defines
    it (s = scale, on the coordinate offset by a tiny epsilon as Blender does)."""

    color1: Input = (0.8, 0.8, 0.8)
    color2: Input = (0.2, 0.2, 0.2)
    scale: float = 5.0
    coords: str = "generated"
    mapping: np.ndarray | None = None


@dataclass
class MixColor:
    """Blender's Mix node in Color mode (and the legacy MixRGB): blend(a, b) by `factor` in [0, 1]."""

    a: Input = (0.5, 0.5, 0.5)
    b: Input = (0.5, 0.5, 0.5)
    factor: Input = 0.5
    blend: str = "MIX"
    clamp_factor: bool = True
    clamp_result: bool = False


@dataclass
class SeparateColor:
    """Blender's Separate Color (and the legacy Separate RGB / HSV / XYZ): one channel (0, 1, 2) of `color` in
    `mode` (RGB, HSV or HSL). A number: read by a value input it is that channel exactly."""

    color: Input = (0.8, 0.8, 0.8)
    channel: int = 0
    mode: str = "RGB"


@dataclass
class CombineColor:
    """Blender's Combine Color (and the legacy Combine RGB / HSV / XYZ): a colour of three numbers in `mode`."""

    r: Input = 0.0
    g: Input = 0.0
    b: Input = 0.0
    mode: str = "RGB"


@dataclass
class Math:
    """Blender's Math node on numbers (a colour input is read as its luminance): `op` of MATH_OPS on a, b, c;
    `clamp` to [0, 1] after. A number."""

    op: str = "ADD"
    a: Input = 0.5
    b: Input = 0.5
    c: Input = 0.0
    clamp: bool = False


@dataclass
class VectorMath:
    """Blender's Vector Math node on colours taken as vectors: `op` of VECTOR_OPS on a, b (`scale` for SCALE).
    DOT_PRODUCT, LENGTH and DISTANCE give a number, the others a vector."""

    op: str = "ADD"
    a: Input = (0.0, 0.0, 0.0)
    b: Input = (0.0, 0.0, 0.0)
    scale: Input = 1.0


@dataclass
class Invert:
    """Blender's Invert Color: color blended towards 1 - color by `factor`."""

    color: Input = (0.0, 0.0, 0.0)
    factor: Input = 1.0


@dataclass
class HueSaturationValue:
    """Blender's Hue/Saturation/Value node: `color` in HSV, its hue turned by `hue` - 0.5, its saturation scaled by
    `saturation` (then clamped to [0, 1]) and its value by `value`; blended with `color` by `factor`, then clamped
    at 0."""

    color: Input = (0.8, 0.8, 0.8)
    hue: Input = 0.5
    saturation: Input = 1.0
    value: Input = 1.0
    factor: Input = 1.0


@dataclass
class ColorRamp:
    """Blender's Color Ramp (RGB colour mode): `factor` looked up among the stops (`positions` in [0, 1], each with
    an rgba of `colors`), clamped to the first and last stop; between stops LINEAR blends, EASE blends by
    smoothstep, CONSTANT takes the stop at or below. `alpha`: the node's Alpha output (a number) instead of Color."""

    factor: Input = 0.5
    positions: tuple = (0.0, 1.0)
    colors: tuple = ((0.0, 0.0, 0.0, 1.0), (1.0, 1.0, 1.0, 1.0))
    interpolation: str = "LINEAR"
    alpha: bool = False


@dataclass
class RGBCurves:
    """Blender's RGB Curves: each channel of `color` through its curve after the combined curve, as a table of
    `table` rows (r, g, b) sampled evenly over [lo, hi] (Blender's CurveMapping evaluated there: the exporter fills
    it, as Cycles fills its own 256-entry table) and read with linear interpolation; past either end the end rows'
    slope continues the table (`extrapolate`) or its end value holds. Blended with `color` by `factor`."""

    color: Input = (0.8, 0.8, 0.8)
    factor: Input = 1.0
    table: tuple = ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    lo: float = 0.0
    hi: float = 1.0
    extrapolate: bool = True


@dataclass
class Attribute:
    """Blender's Color Attribute node (and the Attribute node of a colour attribute): the mesh's per-corner colour
    attribute `name` (Mesh.attributes) blended over the triangle by barycentrics; 0 where the mesh has none, as in
    Cycles. `output`: "color", "alpha" or "fac" (the Attribute node's Fac: the mean of r, g and b); the last two are
    numbers."""

    name: str = ""
    output: str = "color"


BUMP_STEP = 1e-3  # the bump's step to its neighbour points, in barycentric units of the triangle (textures/bump.h)


@dataclass
class Bump:
    """Blender's Bump node on a Normal input: the shading normal tilted by the surface gradient of `height` (a
    number) times `distance` (negated by `invert`), blended with the untilted normal by `strength`. The gradient
    comes from the height at the point and at two neighbours on its triangle, BUMP_STEP along each edge from the
    first corner; Cycles steps along the ray differentials (a fraction of the pixel): the same gradient where the
    height is smooth over both steps."""

    height: Input = 0.0
    strength: float = 1.0
    distance: float = 1.0
    invert: bool = False


@dataclass
class NormalMap:
    """Blender's Normal Map node, tangent space of the UV map: `color` (a Non-Color image, usually) -> a shading
    normal, blended with the interpolated normal by `strength`."""

    color: Input = (0.5, 0.5, 1.0)
    strength: float = 1.0


Texture = Union[ImageTexture, CheckerTexture, MixColor, NormalMap, SeparateColor, CombineColor, Math, VectorMath,  # noqa: UP007
                Invert, HueSaturationValue, ColorRamp, RGBCurves, Attribute, Bump]
# a material or node input: a number, an rgb triple, or a texture node
Input = Union[float, tuple, Texture]  # noqa: UP007 (the forward references above need Union)

TEXTURE_TYPES = (ImageTexture, CheckerTexture, MixColor, NormalMap, SeparateColor, CombineColor, Math, VectorMath,
                 Invert, HueSaturationValue, ColorRamp, RGBCurves, Attribute, Bump)


def gives_number(node: object) -> bool:
    """Whether a texture node's output is a number (a value input reads it as it is, not as a colour's grey)."""
    if isinstance(node, ColorRamp | ImageTexture):
        return bool(node.alpha)
    if isinstance(node, Attribute):
        return node.output != "color"
    return isinstance(node, SeparateColor | Math) or (isinstance(node, VectorMath) and node.op in VECTOR_VALUE_OPS)


def is_texture(value: object) -> bool:
    return isinstance(value, TEXTURE_TYPES)


def constant_rgb(value: Input, neutral: tuple = (1.0, 1.0, 1.0)) -> tuple[float, float, float]:
    """The colour a constant input holds (a number stands for grey); `neutral` for a texture node."""
    if is_texture(value):
        return neutral
    a = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,))
    return float(a[0]), float(a[1]), float(a[2])


def constant_float(value: Input, neutral: float = 0.0) -> float:
    """The number a constant input holds (a colour's mean); `neutral` for a texture node."""
    if is_texture(value):
        return neutral
    a = np.asarray(value, dtype=np.float64).reshape(-1)
    return float(a[0]) if a.size == 1 else float(a.mean())
