"""Cycles' light passes on the host (Settings.light_passes, feature HAS_LIGHT_PASSES): the planes the kernels write
(opencl/film/light_passes.h: LIGHT_PLANES of render/passes.py, float4 per pixel), and their read-back into a Frame.

The planes hold light before any division: the direct and the bounced light of the first surface's diffuse, glossy
and transmission parts, the emitters and the world the camera sees, and the first surface's diffuse, glossy and
transmission colours. As Cycles does, the Direct and Indirect passes are the light divided by the colour of their
part, so that the compositor's (Direct + Indirect) x Color gives the light back; a channel whose colour is 0 takes
the mean of the channels that could be divided (Cycles' "even" division), and a pixel whose colour is 0 in every
channel gets 0.
A still render divides the sums of its samples (StillAccumulation sums the planes), which keeps the identity
Combined = (DiffDir + DiffInd) DiffCol + (GlossDir + GlossInd) GlossCol + (TransDir + TransInd) TransCol + Emit
+ Env exact for the mean colours.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pyopencl as cl

from ..core.buffers import alloc
from ..settings.table import Settings
from .frame import Frame
from .passes import LIGHT_PLANES

# the Frame field of each divided pass, and the plane of its colour
DIVIDED = {"diffuse_direct": "diffuse_color", "diffuse_indirect": "diffuse_color",
           "glossy_direct": "glossy_color", "glossy_indirect": "glossy_color",
           "transmission_direct": "transmission_color", "transmission_indirect": "transmission_color"}


def light_group_settings(scene, settings: Settings) -> Settings:
    """The settings a renderer of `scene` runs: with light groups, the bounced light of animation and viewport
    frames comes from the path pass, not ReSTIR GI, whose reservoirs hold the light of a secondary point summed over
    every light (its groups cannot be told apart)."""
    return replace(settings, gi_reuse=False) if scene.light_groups and settings.gi_reuse else settings


def planes_buffer(context: cl.Context, pixels: int, groups: int = 0) -> cl.Buffer:
    """The device buffer of the planes of one frame (or of their sums), with `groups` light groups' planes after the
    light passes' (opencl/film/light_groups.h)."""
    return alloc(context, pixels * 16 * (len(LIGHT_PLANES) + groups))


def read_groups(queue: cl.CommandQueue, buf: cl.Buffer, shape: tuple[int, int], names: list[str],
                scale: float = 1.0) -> dict[str, np.ndarray]:
    """The light groups' planes of `buf` by group name, (H, W, 3) float32 each, times `scale`."""
    out = np.empty((len(LIGHT_PLANES) + len(names), *shape, 4), np.float32)
    cl.enqueue_copy(queue, out, buf)
    return {name: np.ascontiguousarray(out[len(LIGHT_PLANES) + k, ..., :3] * np.float32(scale))
            for k, name in enumerate(names)}


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


def fill_planes(out: Frame, queue: cl.CommandQueue, buf: cl.Buffer, light_passes: bool, groups: list[str],
                scale: float = 1.0) -> None:
    """The light passes (where `light_passes`) and the light groups' passes of `out` from the planes in `buf` (a
    frame's, or a still's sums times `scale`)."""
    shape = out.color.shape[:2]
    if light_passes:
        fill_frame(out, read_planes(queue, buf, shape, scale))
    if groups:
        out.light_groups = read_groups(queue, buf, shape, groups, scale)


def fill_frame(out: Frame, planes: dict[str, np.ndarray]) -> None:
    """The light passes of `out` from the planes (one frame's, or a still's means); Diffuse Color (the albedo pass)
    becomes the colour the diffuse light was divided by."""
    for name, colour in DIVIDED.items():
        setattr(out, name, divide_by_colour(planes[name], planes[colour]))
    out.glossy_color = planes["glossy_color"]
    out.transmission_color = planes["transmission_color"]
    out.emission = planes["emission"]
    out.environment = planes["environment"]
    out.albedo = planes["diffuse_color"]
