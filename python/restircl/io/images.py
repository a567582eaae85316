"""Images: EXR with Blender-style layer names through OpenEXR.File, PNG previews through Pillow."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..render.cryptomatte import LAYER_SUFFIX
from ..render.cryptomatte import metadata as cryptomatte_metadata
from ..render.frame import Frame
from ..render.passes import PASSES, exr_names


def exr_channels(frame: Frame) -> dict[str, np.ndarray]:
    """Blender-style channels of every pass in PASSES that the frame holds: R, G, B, A of the Combined image,
    Depth.Z, Normal.XYZ, Vector.XYZW, Noisy.RGB, Albedo.RGB. Depth is the view depth, with misses written as 1e10
    (Blender writes a large finite value)."""
    ch: dict[str, np.ndarray] = {}
    for p in PASSES:
        data = getattr(frame, p.attr, None)
        if data is None:  # left out of the read-back (render_frame(aovs=False))
            continue
        data = np.asarray(data, dtype=np.float32)
        if p.miss is not None:
            data = np.where(np.isfinite(data), data, np.float32(p.miss)).astype(np.float32)
        if data.ndim == 2:
            data = data[..., None]
        for i, name in enumerate(exr_names(p)):
            ch[name] = np.ascontiguousarray(data[..., i])
    for group, data in (frame.light_groups or {}).items():  # Cycles' names: Combined_<group>.R, G, B
        for i, c in enumerate("RGB"):
            ch[f"Combined_{group}.{c}"] = np.ascontiguousarray(data[..., i], dtype=np.float32)
    for kind, data in (frame.cryptomatte or {}).items():  # CryptoObject00.r, g, b, a: two ranks per layer
        padded = np.concatenate([data, np.zeros((*data.shape[:2], -data.shape[-1] % 4), np.float32)], axis=-1)
        for k in range(padded.shape[-1] // 4):
            for i, c in enumerate("rgba"):
                ch[f"{LAYER_SUFFIX[kind]}{k:02d}.{c}"] = np.ascontiguousarray(padded[..., 4 * k + i])
    return ch


def exr_metadata(frame: Frame) -> dict[str, str]:
    """The Cryptomatte layers' metadata (name, hash, conversion, manifest) of a frame that has them."""
    out: dict[str, str] = {}
    for kind, names in (frame.cryptomatte_names or {}).items() if frame.cryptomatte else ():
        out.update(cryptomatte_metadata(LAYER_SUFFIX[kind], names))
    return out


def write_exr(path: str | Path, frame: Frame | np.ndarray) -> None:
    """Write a Frame (colour and AOV layers) or an (H, W, 3|4) float array as a float32 EXR."""
    import OpenEXR

    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    if isinstance(frame, Frame):
        channels = exr_channels(frame)
        header.update(exr_metadata(frame))
    else:
        img = np.asarray(frame, dtype=np.float32)
        channels = {name: np.ascontiguousarray(img[..., i]) for i, name in enumerate("RGBA"[: img.shape[-1]])}
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    OpenEXR.File(header, channels).write(str(path))


def read_exr(path: str | Path) -> dict[str, np.ndarray]:
    """All channels of an EXR file, by name."""
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as f:
        return {name: np.array(ch.pixels) for name, ch in f.channels().items()}


def to_srgb8(rgb: np.ndarray, exposure: float = 0.0) -> np.ndarray:
    """Linear RGB -> 8-bit sRGB with an exposure in stops; NaN/Inf show as black."""
    x = np.nan_to_num(np.asarray(rgb, dtype=np.float64), nan=0.0, posinf=0.0, neginf=0.0) * (2.0**exposure)
    x = np.clip(x, 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (s * 255.0 + 0.5).astype(np.uint8)


def auto_exposure(rgb: np.ndarray) -> float:
    """Exposure (stops) that maps the log-average luminance of the lit pixels to middle grey (0.18), but never
    lets more than 2 % of them clip: lights seen directly stay small bright spots instead of setting the scale."""
    lum = 0.2126 * rgb[..., 0] + 0.7152 * rgb[..., 1] + 0.0722 * rgb[..., 2]
    lum = lum[np.isfinite(lum) & (lum > 0)]
    if lum.size == 0:
        return 0.0
    key = float(np.exp(np.mean(np.log(lum))))
    bright = float(np.percentile(lum, 98.0))
    return float(min(np.log2(0.18 / key), np.log2(1.0 / bright) + 2.0))


def write_png(path: str | Path, rgb: np.ndarray | Frame, exposure: float | None = None) -> None:
    from PIL import Image

    img = rgb.color[..., :3] if isinstance(rgb, Frame) else np.asarray(rgb)[..., :3]
    if exposure is None:
        exposure = auto_exposure(img)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(to_srgb8(img, exposure), "RGB").save(str(path))
