"""One TAA step on hand-made buffers, for the tests of TAA's parts (test_taa_fresh_fill.py, test_taa_clip_surface.py):
the renderer's own TAA stage runs once on a G-buffer, samples and history the test writes."""

from types import SimpleNamespace

import numpy as np
import pyopencl as cl
from restircl import Renderer


def taa_step(r: Renderer, g: np.ndarray, sample: np.ndarray, history: np.ndarray, moving: bool,
             glossy: np.ndarray | None = None, keep_history: bool = True) -> np.ndarray:
    """(H, W, 4) what TAA writes (rgb shown, w the history length) for G-buffer `g` (this frame's and last frame's),
    rgb samples `sample`, last frame's history `history` (rgb, n) and, in a glossy build, G-buffer extension
    `glossy`. keep_history False: a reset (a first frame, a cut)."""
    q, h = r.device.queue, r.history
    height, width = g.shape
    for slot in (h.cur, h.prev):
        cl.enqueue_copy(q, h.gbuf(slot), g)
        if glossy is not None:
            cl.enqueue_copy(q, h.glossy(slot), glossy)
    cl.enqueue_copy(q, h.taa[h.prev], np.ascontiguousarray(history, np.float32))
    rgba = np.concatenate([sample, np.ones((height, width, 1))], axis=2).astype(np.float32)
    cl.enqueue_copy(q, r.buffers.sample, rgba)
    state = SimpleNamespace(frame_params=r.frame_params(), plan=SimpleNamespace(history=keep_history), sweep=(0.0, 0.0))
    out = np.empty((height, width, 4), np.float32)
    cl.enqueue_copy(q, out, r.taa.run(state, moving))  # type: ignore[arg-type]
    return out
