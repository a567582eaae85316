"""Blender images -> the `image` and `colorspace` of a restircl.materials.textures.ImageTexture.

Images saved on disk in a format the renderer reads (PNG, JPEG, EXR) are passed by path and read at upload;
packed, generated, edited-but-unsaved images and other formats are copied out of Blender as arrays (rows top
first, as in an image file, so v = 0 is the bottom row as in Blender). Byte images keep their stored values
(uint8, in their colour space); float images are linear in Blender's memory whatever file they came from, so
their arrays are Non-Color."""

from __future__ import annotations

import os
from collections.abc import Callable

import numpy as np

READABLE = (".png", ".jpg", ".jpeg", ".exr")  # what restircl.io.image_load reads on every install
# colour spaces whose values are taken as stored: scene linear (Blender's working space) and data
LINEAR_EXACT = ("Non-Color", "Raw", "Linear Rec.709", "Linear", "scene_linear", "Utility - Raw")
LINEAR_LIKE = ("Linear", "ACES2065", "ACEScg", "Log")  # linear or log encodings: nearest is "as stored"


def colorspace_of(name: str, note: Callable[[str], None], what: str) -> str:
    """Blender's colour space name -> "sRGB" or "Non-Color"; others become the nearest, with a note."""
    if name in ("sRGB", "") or name in LINEAR_EXACT:  # "": an image Blender could not read (said elsewhere)
        return "sRGB" if name in ("sRGB", "") else "Non-Color"
    nearest = "Non-Color" if any(k in name for k in LINEAR_LIKE) else "sRGB"  # display encodings: sRGB
    note(f"{what}: colour space {name!r} is not supported; read as {nearest}")
    return nearest


def image_data(image, note: Callable[[str], None], what: str) -> tuple[np.ndarray | str, str] | None:
    """(array or path, colour space) of a Blender image, or None (with a note) when it has no pixels to give."""
    import bpy

    source = getattr(image, "source", "FILE")
    if source not in ("FILE", "GENERATED"):
        note(f"{what}: image {image.name!r} of source {source} is not supported; the input's value is used")
        return None
    colorspace = colorspace_of(image.colorspace_settings.name, note, what)
    if source == "FILE" and image.packed_file is None and not image.is_dirty:
        path = bpy.path.abspath(image.filepath_raw or image.filepath, library=image.library)
        if not os.path.isfile(path):
            note(f"{what}: image file {path!r} of {image.name!r} is missing; the input's value is used")
            return None
        if os.path.splitext(path)[1].lower() in READABLE:
            return os.path.normpath(path), colorspace
    pixels = _pixels(image)
    if pixels is None:
        note(f"{what}: image {image.name!r} has no pixels (0x0 or unreadable); the input's value is used")
        return None
    if not np.all(np.isfinite(pixels)):
        note(f"{what}: image {image.name!r} has NaN or infinite pixels; they are read as 0")
        pixels = np.nan_to_num(pixels, nan=0.0, posinf=0.0, neginf=0.0)
    if image.is_float:
        return pixels, "Non-Color"
    return np.round(np.clip(pixels, 0.0, 1.0) * 255.0).astype(np.uint8), colorspace


def _pixels(image) -> np.ndarray | None:
    """(H, W, C) float32, rows top first."""
    try:
        w, h = int(image.size[0]), int(image.size[1])
        c = int(image.channels)
    except (RuntimeError, ReferenceError):
        return None
    if w <= 0 or h <= 0 or c <= 0:
        return None
    buf = np.empty(w * h * c, dtype=np.float32)
    try:
        image.pixels.foreach_get(buf)
    except (RuntimeError, ValueError):
        return None
    return np.ascontiguousarray(buf.reshape(h, w, c)[::-1])
