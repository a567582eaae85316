"""Device buffers: allocation, upload, and the per-frame scratch buffers the stages share."""

from __future__ import annotations

import numpy as np
import pyopencl as cl

from . import layouts as L


def alloc(context: cl.Context, nbytes: int) -> cl.Buffer:
    """A read-write buffer of `nbytes` (at least 16: OpenCL refuses empty buffers)."""
    return cl.Buffer(context, cl.mem_flags.READ_WRITE, max(int(nbytes), 16))


def upload(context: cl.Context, array: np.ndarray) -> cl.Buffer:
    """A read-only copy of `array` on the device (16 zero bytes for an empty one)."""
    data = np.ascontiguousarray(array)
    if data.nbytes == 0:
        data = np.zeros(16, np.uint8)
    return cl.Buffer(context, cl.mem_flags.READ_ONLY | cl.mem_flags.COPY_HOST_PTR, hostbuf=data)


def upload_parts(context: cl.Context, parts: list[np.ndarray]) -> cl.Buffer:
    """A read-only buffer holding `parts` one after the other, written part by part: no host copy of the whole
    (the light buffer with a huge environment map behind its records)."""
    arrays = [np.ascontiguousarray(p) for p in parts if p.nbytes]
    if len(arrays) <= 1:
        return upload(context, arrays[0] if arrays else np.zeros(0, np.uint8))
    buf = cl.Buffer(context, cl.mem_flags.READ_ONLY, sum(a.nbytes for a in arrays))
    queue = cl.CommandQueue(context, context.devices[0])
    at = 0
    for a in arrays:
        cl.enqueue_copy(queue, buf, a, dst_offset=at)
        at += a.nbytes
    queue.finish()
    return buf


class FrameBuffers:
    """What one frame's stages write and read, beside the ping-ponged history (render/history.py)."""

    def __init__(self, context: cl.Context, queue: cl.CommandQueue, pixels: int) -> None:
        n = pixels
        self.res_initial = alloc(context, n * L.RESERVOIR.itemsize)
        self.res_temp = alloc(context, n * L.RESERVOIR.itemsize)
        self.sample = alloc(context, n * 16)  # the noisy estimate s_n of this frame
        self.guards = alloc(context, 4 * L.GUARD_COUNT)
        self.cameras = [alloc(context, L.CAMERA.itemsize) for _ in range(3)]  # current, previous, next
        self.vector = alloc(context, n * 16)
        self.none = alloc(context, 16)  # bound to the tile arguments of kernels that run without tiles
        self.light_passes = self.none  # the light passes' planes (render/light_passes.py), where they are on
        cl.enqueue_fill_buffer(queue, self.guards, np.int32(0), 0, 4 * L.GUARD_COUNT)
