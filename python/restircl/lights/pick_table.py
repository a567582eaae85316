"""The per-pixel light pick of still RIS renders (Settings.light_proposal "pixel", and "auto" on stills of at most
MAX_LIGHTS lights): once per still render, after its first frame's camera rays, every pixel gets its own pick
probabilities over the lights, proportional to each light's estimated unshadowed contribution at the pixel's
surface, mixed with the light array's pdf (FLOOR) so that every light that emits keeps a nonzero probability.
Mirrors opencl/lights/pick_table.h (the row format) and lights/pick_table.cl (the estimate)."""

from __future__ import annotations

import numpy as np
import pyopencl as cl

from ..core.buffers import alloc
from ..core.kernels import Kernels

#: lights/pick_table.h PICK_TABLE_MAX: a row covers at most this many lights (memory: 2 (n - 1) bytes per pixel, 126
#: at 64: 261 MB at 1920 x 1080). Above 16 lights the candidates came from the light array until the tuning garden
#: with 24, 48 and 64 lights measured the table 0.79, 0.68 and 0.37x the array's relMSE x CPU seconds at 64 frames
#: (docs/measurements/error-vs-time.md, "The per-pixel light pick up to 64 lights")
MAX_LIGHTS = 64
#: lights/pick_table.h PICK_TABLE_FLOOR: the light array's share of every probability
FLOOR = 0.25
ONE = 65536


def uses_table(proposal: str, method: str, light_count: int, still: bool) -> bool:
    """Whether frames with this Settings.light_proposal and method pick from the table: only still RIS frames
    (the table is made once per still render), of 2..MAX_LIGHTS lights; `auto` and `pixel` both do."""
    return proposal in ("auto", "pixel") and method == "ris" and still and 2 <= light_count <= MAX_LIGHTS


class PickTable:
    """The device buffer of the rows and whether the frame being rendered has one."""

    def __init__(self, kernels: Kernels, pixels: int) -> None:
        self.kernels = kernels
        self.pixels = pixels
        self.buf: cl.Buffer | None = None
        self.active = False  # a still render picks from the table
        self.ready = False  # the rows of this still render are on the device

    def start(self, on: bool) -> None:
        """A still render begins (on: its frames use the table, made after its first camera rays) or ends."""
        self.active, self.ready = on, False

    def build(self, gbuf: cl.Buffer, glossy: cl.Buffer, lights: cl.Buffer, light_pdf: cl.Buffer, light_count: int,
              frame_params: np.void) -> None:
        n = min(light_count, MAX_LIGHTS)
        nbytes = max(self.pixels * 2 * (n - 1), 16)
        if self.buf is None or self.buf.size < nbytes:
            self.buf = alloc(self.kernels.device.context, nbytes)
        self.kernels.launch("light_pick_table", (self.pixels,), gbuf=gbuf, glossy=glossy, lights=lights,
                            light_pdf=light_pdf, table=self.buf, frame_params=frame_params,
                            light_count=np.int32(n))
        self.ready = True

    def read(self, light_count: int) -> np.ndarray:
        """(pixels, n) pick probabilities of the rows on the device (tests)."""
        n = min(light_count, MAX_LIGHTS)
        assert self.buf is not None
        raw = np.empty(self.pixels * (n - 1), np.uint16)
        cl.enqueue_copy(self.kernels.device.queue, raw, self.buf)
        rows = raw.reshape(self.pixels, n - 1).astype(np.int64)
        cum = np.concatenate([np.zeros((self.pixels, 1), np.int64), rows, np.full((self.pixels, 1), ONE)], axis=1)
        return np.diff(cum, axis=1) / ONE
