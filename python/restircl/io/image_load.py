"""Images for textures: a file (PNG/JPEG/TGA/BMP/TIFF through Pillow, EXR through OpenEXR) or an array -> linear
float RGBA texels, bottom row first (as Blender stores images and as UV v = 0 is the bottom), sRGB decoded.

The texture packer (upload/textures.py) turns every failure here into a warning naming the material and the image.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

# colour spaces read as stored (Blender's names for data and for linear images); "sRGB" is decoded
LINEAR_COLORSPACES = ("Non-Color", "Linear", "Linear Rec.709", "Linear CIE-XYZ E", "Raw", "scene_linear")
PILLOW_SUFFIXES = (".png", ".jpg", ".jpeg", ".tga", ".bmp", ".tif", ".tiff", ".webp")


class ImageReadError(ValueError):
    """An image file is missing, unreadable or of a format this reader does not know."""


def srgb_to_linear(c: np.ndarray) -> np.ndarray:
    """The sRGB transfer function inverted (IEC 61966-2-1), as Blender decodes sRGB images."""
    c = np.asarray(c, dtype=np.float64)
    return np.where(c <= 0.04045, c / 12.92, np.power((np.maximum(c, 0.0) + 0.055) / 1.055, 2.4))


def linear_to_srgb(c: np.ndarray) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1): srgb_to_linear's inverse."""
    c = np.maximum(np.asarray(c, dtype=np.float64), 0.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def read_image_file(path: str | Path) -> np.ndarray:
    """The pixels of an image file, top row first, as the file stores them: (H, W, C) uint8/uint16/float32."""
    path = Path(path)
    if not path.is_file():
        raise ImageReadError(f"image file {str(path)!r} not found")
    suffix = path.suffix.lower()
    if suffix == ".exr":
        return _read_exr(path)
    if suffix not in PILLOW_SUFFIXES:
        raise ImageReadError(f"image file {str(path)!r}: format {suffix or '(none)'} is not readable "
                             f"(readable: .exr, {', '.join(PILLOW_SUFFIXES)})")
    from PIL import Image

    try:
        with Image.open(path) as im:
            im.load()
            if im.mode in ("I;16", "I;16B", "I;16L", "I"):
                # Pillow opens 16-bit PNGs as I;16 or as 32-bit I holding 0..65535
                return np.clip(np.asarray(im, dtype=np.int64), 0, 65535).astype(np.uint16)
            if im.mode == "F":
                return np.asarray(im, dtype=np.float32)
            return np.asarray(im.convert("RGBA" if "A" in im.getbands() else "RGB"))
    except Exception as exc:  # truncated or corrupt files
        raise ImageReadError(f"image file {str(path)!r} is not readable ({type(exc).__name__}: {exc})") from exc


def _read_exr(path: Path) -> np.ndarray:
    import OpenEXR

    try:
        with OpenEXR.File(str(path), separate_channels=True) as f:
            ch = {name: np.array(c.pixels, dtype=np.float32) for name, c in f.channels().items()}
    except Exception as exc:
        raise ImageReadError(f"image file {str(path)!r} is not a readable EXR ({type(exc).__name__}: {exc})") from exc
    for names in (("R", "G", "B", "A"), ("R", "G", "B"), ("Y",)):
        if all(n in ch for n in names):
            return np.stack([ch[n] for n in names], axis=-1)
    raise ImageReadError(f"image file {str(path)!r}: no R, G, B or Y channels (has {', '.join(ch)})")


def to_linear_rgba(pixels: np.ndarray, colorspace: str) -> np.ndarray:
    """(H, W) or (H, W, 1..4) pixels, top row first -> (H, W, 4) float32 linear RGBA, bottom row first. Integers are
    value / max of their type; floats as stored; grey is replicated to RGB; a missing alpha is 1. sRGB decodes RGB."""
    a = np.asarray(pixels)
    if a.ndim == 2:
        a = a[..., None]
    if a.ndim != 3 or a.shape[2] not in (1, 2, 3, 4):
        raise ImageReadError(f"image array must be (H, W) or (H, W, 1..4), got shape {a.shape}")
    if a.dtype.kind in "ui":
        x = a.astype(np.float64) / float(np.iinfo(a.dtype).max)
    elif a.dtype.kind in "fb":
        x = a.astype(np.float64)
    else:
        raise ImageReadError(f"image array of dtype {a.dtype} is not an image")
    c = x.shape[2]
    rgb = np.repeat(x[..., :1], 3, axis=2) if c <= 2 else x[..., :3]
    alpha = x[..., c - 1] if c in (2, 4) else np.ones(x.shape[:2])
    if colorspace == "sRGB":
        rgb = srgb_to_linear(rgb)
    out = np.concatenate([rgb, alpha[..., None]], axis=2)[::-1]
    return np.ascontiguousarray(out, dtype=np.float32)


def mip_chain(level0: np.ndarray, encoded: bool = False) -> list[np.ndarray]:
    """Level 0 and each halved level, rounded up (2x2 box filter; an odd row or column is repeated first), down to
    1x1: the sizes opencl/textures/image.h steps through. With `encoded` (sRGB-encoded colour, decoded after
    filtering) the box filter averages the decoded colour and each level is encoded back, so a level decodes to the
    mean light of its texels, as the average of many point samples does (a minified image of sparse bright texels,
    averaged in its encoding, is several times too dark); level 0 stays as it is."""
    if encoded:
        rgb = mip_chain(srgb_to_linear(level0[..., :3]).astype(np.float32))
        alpha = mip_chain(np.ascontiguousarray(level0[..., 3:]))
        return [level0] + [np.ascontiguousarray(np.concatenate([linear_to_srgb(c), a], axis=-1), dtype=np.float32)
                           for c, a in zip(rgb[1:], alpha[1:], strict=True)]
    levels = [level0]
    a = level0
    while a.shape[0] > 1 or a.shape[1] > 1:
        h, w = a.shape[:2]
        if h > 1 and h % 2:
            a = np.concatenate([a, a[-1:]], axis=0)
        if w > 1 and w % 2:
            a = np.concatenate([a, a[:, -1:]], axis=1)
        if a.shape[0] > 1:
            a = 0.5 * (a[0::2] + a[1::2])
        if a.shape[1] > 1:
            a = 0.5 * (a[:, 0::2] + a[:, 1::2])
        levels.append(np.ascontiguousarray(a, dtype=np.float32))
    return levels
