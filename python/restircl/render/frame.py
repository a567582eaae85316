"""A rendered frame as numpy arrays (the output of Renderer.render_frame and render_still), the same frame while it is
still on the device (DeviceFrame, Renderer.run_frame), and its read-back."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import pyopencl as cl

from ..core import layouts as L
from . import cryptomatte
from .index_passes import index_images


@dataclass
class Frame:
    """One rendered frame: (H, W, ...) float32 arrays, row 0 at the top."""

    color: np.ndarray  # (H, W, 4) RGBA: TAA output (animation) or the accumulated mean (still)
    noisy: np.ndarray  # (H, W, 3) the last 1-sample direct light estimate s_n (emission included)
    # the passes below are None when render_frame(..., aovs=False) left their read-back out
    depth: np.ndarray | None  # (H, W) view depth, inf where the camera ray missed
    normal: np.ndarray | None  # (H, W, 3) world shading normal
    vector: np.ndarray | None  # (H, W, 4) Blender-style Vector pass: xy to the previous frame, zw to the next
    albedo: np.ndarray | None  # (H, W, 3)
    frame: int = 0
    samples: int = 1
    ms: float = 0.0
    stage_ms: dict[str, float] = field(default_factory=dict)
    guards: dict[str, int] = field(default_factory=dict)
    features: list[str] = field(default_factory=list)
    error_estimate: float | None = None  # relMSE estimated from two half buffers (still renders)
    noisy_image: np.ndarray | None = None  # (H, W, 4) the colour before denoising (Settings.denoise), else None
    # Cycles' light passes (Settings.light_passes, render/light_passes.py), (H, W, 3) each, else None
    diffuse_direct: np.ndarray | None = None
    diffuse_indirect: np.ndarray | None = None
    glossy_direct: np.ndarray | None = None
    glossy_indirect: np.ndarray | None = None
    glossy_color: np.ndarray | None = None
    transmission_direct: np.ndarray | None = None
    transmission_indirect: np.ndarray | None = None
    transmission_color: np.ndarray | None = None
    emission: np.ndarray | None = None
    environment: np.ndarray | None = None
    coverage: np.ndarray | None = None  # (H, W) still renders of transparent scenes: the mean coverage (film alpha)
    # light groups (Scene.light_groups, render/light_passes.py read_groups): name -> (H, W, 3) light of its emitters
    light_groups: dict[str, np.ndarray] | None = None
    # the pass indices of the object and the material hit (render/index_passes.py), (H, W)
    object_index: np.ndarray | None = None
    material_index: np.ndarray | None = None
    # Cryptomatte (Settings.cryptomatte_levels, render/cryptomatte.py): kind -> (H, W, 2 * levels) id, coverage
    cryptomatte: dict[str, np.ndarray] | None = None
    cryptomatte_names: dict[str, list[str]] | None = None  # kind -> the names of its ids (for the manifest)
    holdout: np.ndarray | None = None  # (H, W) bool: the camera ray met a holdout (Mesh.holdout): alpha 0 there
    # (H, W, 2) still renders with a holdout: the shares of the samples whose camera ray met a holdout, and nothing
    holdout_shares: np.ndarray | None = None


class DeviceFrame(NamedTuple):
    """A frame rendered and not read back (Renderer.run_frame): what Renderer.read_frame reads."""

    stage_ms: dict[str, float]  # milliseconds per stage
    color: cl.Buffer  # the colour shown: TAA output (animation), or the noisy sample where there is no TAA
    gbuf: cl.Buffer  # its G-buffer (the history slot it was written to)


def read_image(queue: cl.CommandQueue, buf: cl.Buffer, shape: tuple[int, int]) -> np.ndarray:
    """(H, W, 4) float32 copy of a float4 image buffer."""
    out = np.empty((*shape, 4), np.float32)
    cl.enqueue_copy(queue, out, buf)
    return out


def read_colour(queue: cl.CommandQueue, color_buf: cl.Buffer, noisy_buf: cl.Buffer, shape: tuple[int, int],
                scale: float = 1.0) -> tuple[np.ndarray, np.ndarray, int]:
    """(H, W, 4) colour times `scale` (alpha 1), the (H, W, 3) noisy sample, and the count of pixels whose colour
    was NaN/Inf and is 0 now (the kernels guard already; this keeps a NaN from ever leaving the renderer)."""
    color = read_image(queue, color_buf, shape)
    noisy = read_image(queue, noisy_buf, shape)
    rgb = color[..., :3]
    if scale != 1.0:
        rgb *= np.float32(scale)
    count = 0
    if not np.isfinite(rgb).all():
        bad = ~np.isfinite(rgb)
        rgb[bad] = 0.0
        count = int(bad.any(axis=-1).sum())
    color[..., 3] = 1.0
    # noisy: a (H, W, 3) view of the RGBA read-back (a copy cost ~1.5 ms per 640x360 frame)
    return color, noisy[..., :3], count


def read_gbuffer(queue: cl.CommandQueue, gbuf: cl.Buffer, shape: tuple[int, int]) -> np.ndarray:
    """(H, W) GSample records of a G-buffer."""
    g = np.empty(shape[0] * shape[1], L.GSAMPLE)
    cl.enqueue_copy(queue, g, gbuf)
    return g.reshape(shape)


def read_guards(queue: cl.CommandQueue, guard_buf: cl.Buffer, totals: dict[str, int]) -> dict[str, int]:
    """Add the guard counters the kernels left to `totals`, zero them on the device; returns a copy of the totals."""
    g = np.zeros(L.GUARD_COUNT, np.int32)
    cl.enqueue_copy(queue, g, guard_buf)
    cl.enqueue_fill_buffer(queue, guard_buf, np.int32(0), 0, 4 * L.GUARD_COUNT)
    for i, name in enumerate(L.GUARD_NAMES[: L.GUARD_COUNT]):
        totals[name] += int(g[i])
    return dict(totals)


def surface_images(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(H, W, 3) albedo and shading normal of a read-back G-buffer, 0 where the camera ray missed."""
    hit = (L.float_bits_to_int(g["normal"][..., 3]) >= 0)[..., None]
    albedo = np.where(hit, g["albedo"][..., :3], 0.0).astype(np.float32)
    return albedo, np.where(hit, g["normal"][..., :3], 0.0).astype(np.float32)


def read_aovs(queue: cl.CommandQueue, out: Frame, gbuf: cl.Buffer, vector_buf: cl.Buffer, scene=None,
              crypto_levels: int = 0) -> None:
    """Fill the depth, normal, vector and albedo passes of `out` from a G-buffer and the Vector buffer, and, given
    the `scene` it shows, the index passes and (crypto_levels > 0) this frame's Cryptomatte."""
    shape = out.color.shape[:2]
    g = read_gbuffer(queue, gbuf, shape)
    hit = L.float_bits_to_int(g["normal"][..., 3]) != -1  # -1: a miss; below: a light seen (lights/camera_visible.h)
    out.albedo, out.normal = surface_images(g)
    vector = read_image(queue, vector_buf, shape)
    vector[..., 1] *= -1.0  # Blender's pixel y points up
    vector[..., 3] *= -1.0
    out.depth = np.where(hit, g["pos"][..., 3], np.inf).astype(np.float32)
    out.vector = vector
    if scene is not None:
        out.object_index, out.material_index = index_images(g, scene)
        if crypto_levels:
            out.cryptomatte = cryptomatte.from_gbuffer(g, scene, crypto_levels)
            out.cryptomatte_names = {k: cryptomatte.kind_names(scene, k) for k in cryptomatte.KINDS}
    # a holdout is a miss that names the object it met (camera/primary.cl)
    out.holdout = ~hit & (L.float_bits_to_int(g["albedo"][..., 3]) >= 0)
