"""The weighted layers of a still (opencl/camera/layers.h): in a transparent scene, each frame of a still render
shades the partly transparent surfaces along a pixel's camera ray one layer at a time, each with its coverage times
what the surfaces before it let through, as Cycles weights them, instead of the stochastic choice of one surface
per pixel that animation frames keep (ReSTIR DI and GI, TAA and the motion vectors read one primary hit per pixel).

A frame runs the primary pass, the direct light and the path pass once per layer and sums the layers' samples by
their weights (still/layers.cl); a layer's camera ray starts where the last one passed its surface, and the frame
ends when no pixel goes on (at most Transparent Max Bounces + 1 layers: every layer after the first passed a
surface). Stills that need more of the G-buffer than its colour keep the stochastic choice: ReSTIR's reuse (its
reservoirs are one per pixel and frame), the denoiser's guides, Cryptomatte, light passes and groups, holdouts
and objects hidden from the camera (docs/design.md, "Transparency").
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pyopencl as cl

from ..core import layouts as L
from ..core.buffers import alloc
from .plan import FramePlan
from .stages import FrameState, Stage, StageTimer, Untimed, pixel_count

#: flags under which a still keeps one stochastic surface per pixel (the module's docstring says why)
ONE_SURFACE_FLAGS = ("HAS_LIGHT_PASSES", "HAS_LIGHT_GROUPS", "HAS_HOLDOUT", "HAS_CAMERA_HIDDEN")


class CameraLayers(Stage):
    """The per-pixel state between a frame's layers, their weighted sum and the count of pixels that go on."""

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.state: cl.Buffer | None = None  # allocated when first used
        self.sum: cl.Buffer | None = None
        self.continuing: cl.Buffer | None = None
        self.first: tuple[cl.Buffer, cl.Buffer] | None = None  # the first layer's G-buffer and Vector pass
        self.layered = False  # whether the last frame ran more than one layer

    def wanted(self, flags: dict, plan: FramePlan, still: bool) -> bool:
        """Whether this frame shades in weighted layers."""
        s = self.settings
        return (still and bool(flags.get("HAS_TRANSPARENCY")) and plan.method != "restir" and not plan.gi
                and not plan.taa and not s.denoise and not s.cryptomatte_levels
                and not any(flags.get(f) for f in ONE_SURFACE_FLAGS))

    def run(self, state: FrameState, timer: StageTimer, shade: Callable[[FrameState, StageTimer, int], None],
            layered: bool) -> None:
        """shade(state, timer, layer) once (layer -1: one stochastic surface), or per weighted layer of a still
        until no pixel goes on, summing them; the later layers are timed together ("layers"), without waiting
        between their stages."""
        for layer in range(self.max_layers()) if layered else (-1,):
            shade(state, timer if layer <= 0 else Untimed(), layer)  # type: ignore[arg-type]
            if layered and not self.add(state, layer):
                break
        if layered:
            self.finish()
            timer.mark("layers")

    def max_layers(self) -> int:
        return int(self.settings.transparent_max_bounces) + 1

    def arguments(self, layer: int) -> dict:
        """The primary pass's layer arguments: layer -1 (one stochastic surface) needs no buffers."""
        if layer < 0:
            none = self.buffers.none
            return {"layers": none, "layers_continuing": none, "layer": np.int32(-1)}
        if self.state is None:
            context = self.kernels.device.context
            pixels = self.history.pixels
            self.state, self.sum, self.continuing = alloc(context, pixels * 32), alloc(context, pixels * 16), \
                alloc(context, 8)
            self.first = (alloc(context, pixels * L.GSAMPLE.itemsize), alloc(context, pixels * 16))
            # the two counters, by a layer's parity; each frame's last layer_add leaves both 0 (still/layers.cl)
            cl.enqueue_fill_buffer(self.kernels.device.queue, self.continuing, np.int32(0), 0, 8)
        return {"layers": self.state, "layers_continuing": self.continuing, "layer": np.int32(layer)}

    def add(self, state: FrameState, layer: int) -> bool:
        """Add layer `layer`'s sample to the frame's sum by its weights; whether some pixel goes on."""
        h = self.history
        self.kernels.launch("layer_add", pixel_count(state), gbuf=h.gbuf(h.cur), sample=self.buffers.sample,
                            layered=self.sum, continuing=self.continuing, frame_params=state.frame_params,
                            layer=np.int32(layer))
        q = self.kernels.device.queue
        count = np.zeros(1, np.int32)
        cl.enqueue_copy(q, count, self.continuing, src_offset=4 * (layer & 1))
        if layer == 0 and count[0] > 0:  # what the passes show (depth, normals, vectors): the first layer's
            assert self.first is not None
            cl.enqueue_copy(q, self.first[0], h.gbuf(h.cur))
            cl.enqueue_copy(q, self.first[1], self.buffers.vector)
        self.layered = layer > 0
        return bool(count[0] > 0)

    def finish(self) -> None:
        """The frame's sample is the layers' sum; its G-buffer and Vector pass the first layer's."""
        assert self.sum is not None and self.first is not None
        q, h = self.kernels.device.queue, self.history
        cl.enqueue_copy(q, self.buffers.sample, self.sum)
        if self.layered:
            cl.enqueue_copy(q, h.gbuf(h.cur), self.first[0])
            cl.enqueue_copy(q, self.buffers.vector, self.first[1])
