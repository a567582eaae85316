"""Validation of materials and their texture nodes (Scene.validate): SceneError naming the material and the field.

A closure is checked on the fields its kind reads (materials/closures/: ClosureKind.fields), each by its rule in
FIELD_RULES. Ranges follow what Blender allows on the nodes: Metallic, Roughness, Specular IOR Level and a Mix
factor in [0, 1], IOR > 0, colours >= 0, names from the lists in materials/material.py / materials/textures.py.
What only shows when the images are read (a missing file, a 0x0 image, an unsupported colour space, NaN texels) is
a warning at upload (upload/textures.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from . import textures as tx
from .alpha import AlphaError, alpha_source
from .closures.registry import KINDS
from .material import DISTRIBUTIONS, MAX_LAYERS, Material
from .textures import COORDS, EXTENSIONS, INTERPOLATIONS, MIX_BLENDS, CheckerTexture, ImageTexture, MixColor, NormalMap
from .textures import is_texture as _is_texture

RANGE_SLACK = 1e-6


class MaterialError(ValueError):
    """Raised inside this module; Scene.validate turns it into a SceneError with the material's label."""


def check_material(m: Material) -> None:
    """Raise MaterialError naming the first bad field of m (its layers' fields as 'layer k: field')."""
    if m.layers:
        if len(m.layers) > MAX_LAYERS:
            raise MaterialError(f"has {len(m.layers)} layers, at most {MAX_LAYERS}")
        for k, layer in enumerate(m.layers):
            if not isinstance(layer, Material):
                raise MaterialError(f"layer {k} is not a Material ({type(layer).__name__})")
            if layer.layers:
                raise MaterialError(f"layer {k} {layer.name!r} has layers of its own (nest Mix/Add at most once)")
            try:
                _check_closure(layer)
            except MaterialError as exc:
                raise MaterialError(f"layer {k} {layer.name!r}: {exc}") from None
        if m.mix is not None:
            _check_input(m.mix, "mix", colour=False, unit=True)
    else:
        _check_closure(m)
    _check_input(m.emission, "emission", colour=True)
    _check_alpha(m.alpha)
    if not isinstance(m.emission_strength, int | float) or not math.isfinite(m.emission_strength) \
            or m.emission_strength < 0:
        raise MaterialError(f"emission_strength must be finite and >= 0, got {m.emission_strength!r}")


def _check_alpha(value: object) -> None:
    try:
        source = alpha_source(value)  # type: ignore[arg-type]
    except AlphaError as exc:
        raise MaterialError(str(exc)) from None
    if source.image is not None:
        check_node(value, "alpha")


def _check_closure(m: Material) -> None:
    if m.kind not in KINDS:
        raise MaterialError(f"kind must be one of {tuple(KINDS)}, got {m.kind!r}")
    for name in KINDS[m.kind].fields:
        FIELD_RULES[name](getattr(m, name), name)


def _colour(value: object, name: str) -> None:
    _check_input(value, name, colour=True)


def _unit(value: object, name: str) -> None:
    _check_input(value, name, colour=False, unit=True)


def _ior(value: object, name: str) -> None:
    if not isinstance(value, int | float) or not math.isfinite(value) or value <= 0:
        raise MaterialError(f"{name} must be finite and > 0, got {value!r}")


def _unit_number(value: object, name: str) -> None:
    if not isinstance(value, int | float) or not 0 <= value <= 1 + RANGE_SLACK:
        raise MaterialError(f"{name} must be a number in [0, 1], got {value!r}")


def _flag(value: object, name: str) -> None:
    if not isinstance(value, bool):
        raise MaterialError(f"{name} must be True or False, got {value!r}")
def _thickness(value: object, name: str) -> None:
    if not isinstance(value, int | float) or not math.isfinite(value) or value < 0:
        raise MaterialError(f"{name} must be a finite number >= 0 (nm), got {value!r}")


def _distribution(value: object, name: str) -> None:
    if value not in DISTRIBUTIONS:
        raise MaterialError(f"{name} must be one of {DISTRIBUTIONS}, got {value!r}")


def _normal(value: object, name: str) -> None:
    if value is not None:
        if not isinstance(value, NormalMap | tx.Bump):
            raise MaterialError(f"{name} must be a NormalMap or Bump node or None, got {type(value).__name__}")
        check_node(value, name)


# A closure field -> its rule, rule(value, field name), raising MaterialError naming the field
FIELD_RULES: dict[str, Callable[[object, str], None]] = {
    "albedo": _colour, "metallic": _unit, "roughness": _unit, "ior": _ior, "specular": _unit,
    "specular_tint": _colour, "distribution": _distribution, "normal": _normal, "transmission": _unit_number,
    "thin_wall": _flag,
    "thin_film_thickness": _thickness, "thin_film_ior": _ior,
}


def _check_input(value: object, what: str, colour: bool, unit: bool = False) -> None:
    if _is_texture(value):
        if isinstance(value, NormalMap | tx.Bump):
            raise MaterialError(f"{what}: a {type(value).__name__} gives a normal, not a "
                                f"{'colour' if colour else 'value'}")
        check_node(value, what)
        return
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise MaterialError(f"{what} must be a number, an rgb triple or a texture node, got {value!r}") from None
    if colour and a.shape != (3,):
        raise MaterialError(f"{what} must be 3 numbers (rgb), got {value!r}")
    if not colour and a.shape not in ((), (1,), (3,)):
        raise MaterialError(f"{what} must be a number, got {value!r}")
    if not np.all(np.isfinite(a)):
        raise MaterialError(f"{what} must be finite, got {value!r}")
    if np.any(a < 0):
        raise MaterialError(f"{what} must not be negative, got {value!r}")
    if unit and np.any(a > 1 + RANGE_SLACK):
        raise MaterialError(f"{what} must be in [0, 1], got {value!r}")


def check_node(node: object, what: str) -> None:
    """The node's fields and, recursively, its input nodes'; a node reached again through its own inputs is a loop."""
    _check_node(node, what, [])


def _check_node(node: object, what: str, path: list[object]) -> None:
    if any(p is node for p in path):
        raise MaterialError(f"{what}: its texture nodes form a loop through a {type(node).__name__}")
    path = [*path, node]
    label = f"{what}: {type(node).__name__}"
    if isinstance(node, ImageTexture | CheckerTexture):
        if node.coords not in COORDS:
            raise MaterialError(f"{label}: coords must be one of {COORDS}, got {node.coords!r}")
        if node.mapping is not None:
            m = np.asarray(node.mapping, dtype=np.float64)
            if m.shape != (4, 4) or not np.all(np.isfinite(m)):
                raise MaterialError(f"{label}: mapping must be a finite 4x4 matrix, got shape {m.shape}")
    if isinstance(node, ImageTexture):
        if node.interpolation not in INTERPOLATIONS:
            raise MaterialError(f"{label}: interpolation must be one of {INTERPOLATIONS}, got {node.interpolation!r}")
        if node.extension not in EXTENSIONS:
            raise MaterialError(f"{label}: extension must be one of {EXTENSIONS}, got {node.extension!r}")
        if not isinstance(node.image, str | Path | np.ndarray):
            raise MaterialError(f"{label}: image must be an array or a file path, got {type(node.image).__name__}")
        if not isinstance(node.colorspace, str):
            raise MaterialError(f"{label}: colorspace must be a name, got {node.colorspace!r}")
    elif isinstance(node, CheckerTexture):
        if not isinstance(node.scale, int | float) or not math.isfinite(node.scale):
            raise MaterialError(f"{label}: scale must be finite, got {node.scale!r}")
        for name in ("color1", "color2"):
            _sub(getattr(node, name), f"{label}.{name}", True, path)
    elif isinstance(node, MixColor):
        if node.blend not in MIX_BLENDS:
            raise MaterialError(f"{label}: blend must be one of {MIX_BLENDS}, got {node.blend!r}")
        _sub(node.a, f"{label}.a", True, path)
        _sub(node.b, f"{label}.b", True, path)
        _sub(node.factor, f"{label}.factor", False, path)
    elif isinstance(node, NormalMap):
        if not isinstance(node.strength, int | float) or not math.isfinite(node.strength) or node.strength < 0:
            raise MaterialError(f"{label}: strength must be finite and >= 0, got {node.strength!r}")
        _sub(node.color, f"{label}.color", True, path)
    else:
        _check_converter(node, label, path)


# per converter node: (the table its option takes a value of, that option, its inputs as (name, is a colour))
CONVERTERS = {
    tx.SeparateColor: (tx.COLOR_MODES, "mode", (("color", True),)),
    tx.CombineColor: (tx.COLOR_MODES, "mode", (("r", False), ("g", False), ("b", False))),
    tx.Math: (tx.MATH_OPS, "op", (("a", False), ("b", False), ("c", False))),
    tx.VectorMath: (tx.VECTOR_OPS, "op", (("a", True), ("b", True), ("scale", False))),
    tx.Invert: ((), "", (("color", True), ("factor", False))),
    tx.HueSaturationValue: ((), "", (("color", True), ("hue", False), ("saturation", False), ("value", False),
                                     ("factor", False))),
    tx.ColorRamp: (tx.RAMP_INTERPOLATIONS, "interpolation", (("factor", False),)),
    tx.RGBCurves: ((), "", (("color", True), ("factor", False))),
    tx.Attribute: (tx.ATTRIBUTE_OUTPUTS, "output", ()),
    tx.Bump: ((), "", (("height", False),)),
}


def _check_converter(node: object, label: str, path: list[object]) -> None:
    table, option, inputs = CONVERTERS[type(node)]
    if option and getattr(node, option) not in table:
        raise MaterialError(f"{label}: {option} must be one of {table}, got {getattr(node, option)!r}")
    if isinstance(node, tx.SeparateColor) and node.channel not in (0, 1, 2):
        raise MaterialError(f"{label}: channel must be 0, 1 or 2, got {node.channel!r}")
    if isinstance(node, tx.ColorRamp):
        _check_ramp(node, label)
    if isinstance(node, tx.RGBCurves):
        _check_curves(node, label)
    if isinstance(node, tx.Bump) and not all(isinstance(v, int | float) and math.isfinite(v)
                                             for v in (node.strength, node.distance)):
        raise MaterialError(f"{label}: strength and distance must be finite numbers")
    if isinstance(node, tx.Attribute) and not isinstance(node.name, str):
        raise MaterialError(f"{label}: name must be a string, got {node.name!r}")
    for name, colour in inputs:
        _sub(getattr(node, name), f"{label}.{name}", colour, path)


def _check_ramp(node: tx.ColorRamp, label: str) -> None:
    try:
        pos = np.asarray(node.positions, np.float64).reshape(-1)
        cols = [np.asarray(c, np.float64).reshape(-1) for c in node.colors]
    except (TypeError, ValueError) as exc:
        raise MaterialError(f"{label}: positions and colors must be numbers ({exc})") from exc
    if len(pos) == 0 or len(pos) != len(cols):
        raise MaterialError(f"{label}: needs as many positions as colors, at least one, got {len(pos)} and "
                            f"{len(cols)}")
    if any(c.size not in (3, 4) for c in cols) or not np.all(np.isfinite(pos)) or \
            not all(np.all(np.isfinite(c)) for c in cols):
        raise MaterialError(f"{label}: positions must be finite numbers and colors finite rgb or rgba")


def _check_curves(node: tx.RGBCurves, label: str) -> None:
    try:
        table = np.asarray(node.table, np.float64)
        lo, hi = float(node.lo), float(node.hi)
    except (TypeError, ValueError) as exc:
        raise MaterialError(f"{label}: table, lo and hi must be numbers ({exc})") from exc
    if table.ndim != 2 or table.shape[1] != 3 or len(table) < 2 or not np.all(np.isfinite(table)):
        raise MaterialError(f"{label}: table must be at least 2 finite (r, g, b) rows, got shape {table.shape}")
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
        raise MaterialError(f"{label}: needs finite lo < hi, got {lo!r}, {hi!r}")


def _sub(value: object, what: str, colour: bool, path: list[object]) -> None:
    if _is_texture(value):
        if isinstance(value, NormalMap | tx.Bump):
            raise MaterialError(f"{what}: a {type(value).__name__} gives a normal, not a colour")
        _check_node(value, what, path)
    else:
        _check_input(value, what, colour)
