"""Cycles' light passes on the host (Settings.light_passes, feature HAS_LIGHT_PASSES): the planes the kernels write
(opencl/film/light_passes.h: LIGHT_PLANES of render/passes.py, float4 per pixel), and their read-back into a Frame.

The planes hold light before any division: the direct and the bounced light of the first surface's diffuse and
glossy parts, the emitters and the world the camera sees, and the first surface's diffuse and glossy colours. As
Cycles does, the Direct and Indirect passes are the light divided by the colour of their part, so that the
compositor's (Direct + Indirect) x Color gives the light back; a channel whose colour is 0 takes the mean of the
channels that could be divided (Cycles' "even" division), and a pixel whose colour is 0 in every channel gets 0.
A still render divides the sums of its samples (StillAccumulation sums the planes), which keeps the identity
Combined = (DiffDir + DiffInd) DiffCol + (GlossDir + GlossInd) GlossCol + Emit + Env exact for the mean colours.
"""

from __future__ import annotations

import numpy as np
import pyopencl as cl

from ..core.buffers import alloc
from .frame import Frame
from .passes import LIGHT_PLANES

# the Frame field of each divided pass, and the plane of its colour
DIVIDED = {"diffuse_direct": "diffuse_color", "diffuse_indirect": "diffuse_color",
           "glossy_direct": "glossy_color", "glossy_indirect": "glossy_color"}


def planes_buffer(context: cl.Context, pixels: int) -> cl.Buffer:
    """The device buffer of the planes of one frame (or of their sums)."""
    return alloc(context, pixels * 16 * len(LIGHT_PLANES))


def read_planes(queue: cl.CommandQueue, buf: cl.Buffer, shape: tuple[int, int], scale: float = 1.0
                ) -> dict[str, np.ndarray]:
    """Every plane of `buf` as (H, W, 3) float32, times `scale` (a still's sums: 1 / samples)."""
    out = np.empty((len(LIGHT_PLANES), *shape, 4), np.float32)
    cl.enqueue_copy(queue, out, buf)
    rgb = out[..., :3] * np.float32(scale) if scale != 1.0 else out[..., :3]
    return {name: np.ascontiguousarray(rgb[k]) for k, name in enumerate(LIGHT_PLANES)}


def divide_by_colour(light: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """light / colour per channel; a channel of colour 0 takes the mean of the pixel's divided channels (0 where
    none is)."""
    ok = colour > 0
    q = np.where(ok, light / np.where(ok, colour, 1.0), 0.0)
    n = ok.sum(axis=-1, keepdims=True)
    mean = q.sum(axis=-1, keepdims=True) / np.maximum(n, 1)
    return np.where(ok, q, mean).astype(np.float32)


def fill_frame(out: Frame, planes: dict[str, np.ndarray]) -> None:
    """The light passes of `out` from the planes (one frame's, or a still's means); Diffuse Color (the albedo pass)
    becomes the colour the diffuse light was divided by."""
    for name, colour in DIVIDED.items():
        setattr(out, name, divide_by_colour(planes[name], planes[colour]))
    out.glossy_color = planes["glossy_color"]
    out.emission = planes["emission"]
    out.environment = planes["environment"]
    out.albedo = planes["diffuse_color"]
