"""The environment's texels on the host: its image (an array, or a file read by io/image_load.py; Radiance .hdr files
by the reader here) as (H, W, 3) float32 linear RGB, row 0 at the zenith, with
NaN, Inf and negative texels zeroed and counted (one warning naming the world, never a failed render)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ..io.image_load import ImageReadError, read_image_file, to_linear_rgba
from .world import Environment, WorldError


def environment_texels(env: Environment) -> tuple[np.ndarray, int]:
    """(H, W, 3) float32 radiance per unit strength (the image, or the colour where there is none, as a texture
    linked to the Background's Color replaces it in Blender), and how many texels were zeroed."""
    color = np.asarray(env.color, np.float32)
    if env.image is None and env.path is None:
        return color.reshape(1, 1, 3).copy(), 0
    rgb = environment_rgb(env)
    bad = ~np.all(np.isfinite(rgb), axis=2) | np.any(rgb < 0, axis=2)
    count = int(np.count_nonzero(bad))
    if count:
        rgb = rgb.copy()
        rgb[bad] = 0.0
        warnings.warn(f"world {env.name!r}: {count} texel(s) of its image are NaN, Inf or negative; they are black",
                      stacklevel=3)
    return np.ascontiguousarray(rgb, np.float32), count


def environment_rgb(env: Environment) -> np.ndarray:
    """(H, W, 3) float32 of the world's image or file as they are (not cleaned; a view of a float32 RGB array)."""
    if env.image is not None:
        a = np.asarray(env.image)
        if a.dtype.kind in "ui":  # float32 holds 8- and 16-bit values exactly; no float64 copy of a huge map
            return a[..., :3].astype(np.float32) * np.float32(1.0 / np.iinfo(a.dtype).max)
        return np.asarray(a[..., :3], np.float32)
    path = Path(str(env.path))
    try:
        if path.suffix.lower() == ".hdr":
            return read_radiance_hdr(path)
        pixels = read_image_file(path)
    except (ImageReadError, OSError, ValueError) as exc:
        raise WorldError(f"world {env.name!r}: {exc}") from None
    # 8-bit and 16-bit files hold sRGB (Blender's default for them), float files linear values
    space = "sRGB" if np.asarray(pixels).dtype.kind in "ui" else "Linear"
    return np.ascontiguousarray(to_linear_rgba(pixels, space)[::-1, :, :3])  # back to top row first


def read_radiance_hdr(path: Path) -> np.ndarray:
    """A Radiance RGBE file (.hdr: flat or run-length encoded scanlines, -Y H +X W) as (H, W, 3) float32."""
    data = path.read_bytes()
    end = data.find(b"\n\n")
    if not data.startswith(b"#?") or end < 0:
        raise ImageReadError(f"image file {str(path)!r} is not a Radiance HDR file")
    pos = data.find(b"\n", end + 2)
    size = data[end + 2:pos].split()
    if len(size) != 4 or size[0] != b"-Y" or size[2] != b"+X":
        raise ImageReadError(f"image file {str(path)!r}: only -Y H +X W HDR files are read, got {size!r}")
    h, w = int(size[1]), int(size[3])
    buf = np.frombuffer(data, np.uint8, offset=pos + 1)
    rgbe = np.zeros((h, w, 4), np.uint8)
    at = 0
    for y in range(h):
        head = buf[at:at + 4]
        if 8 <= w < 32768 and len(head) == 4 and head[0] == 2 and head[1] == 2 and (head[2] << 8 | head[3]) == w:
            at += 4
            for c in range(4):
                x = 0
                while x < w:
                    n = int(buf[at])
                    at += 1
                    if n > 128:
                        rgbe[y, x:x + n - 128, c] = buf[at]
                        at += 1
                        x += n - 128
                    else:
                        rgbe[y, x:x + n, c] = buf[at:at + n]
                        at += n
                        x += n
        else:
            rgbe[y] = buf[at:at + 4 * w].reshape(w, 4)
            at += 4 * w
    scale = np.where(rgbe[..., 3] > 0, np.ldexp(1.0, rgbe[..., 3].astype(np.int32) - 136), 0.0)
    return (rgbe[..., :3] * scale[..., None]).astype(np.float32)
