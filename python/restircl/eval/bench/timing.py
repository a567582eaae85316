"""How the benchmarks time a frame: median wall ms and mean ms per stage after warm-up frames."""

from __future__ import annotations

import time

import numpy as np

from ...render.pipeline import Renderer
from ...scene.scene import Scene
from ...settings.table import Settings


def time_frames(scene: Scene, settings: Settings, frames: int = 6, warmup: int = 3, device=None,
                still: bool = False, renderer: Renderer | None = None) -> tuple[float, dict[str, float]]:
    """Median ms per frame and mean ms per stage, after warm-up frames (program build, first upload). A frame is
    every pass and the read-back of the image (colour and noisy sample; the G-buffer passes are left out).
    `renderer`: one already built for this scene and settings (else one is built here)."""
    r = renderer or Renderer(scene, settings, device)
    n = scene.frames
    for i in range(warmup):
        r.render_frame(0 if still else i % n, still=still, aovs=False)
    ms, cpu, stages = [], [], {}
    for i in range(warmup, warmup + frames):
        c0 = time.process_time()
        f = r.render_frame(0 if still else i % n, still=still, aovs=False)
        cpu.append((time.process_time() - c0) * 1e3)
        ms.append(f.ms)
        for k, v in f.stage_ms.items():
            stages[k] = stages.get(k, 0.0) + v / frames
    stages["cpu"] = float(np.median(cpu))  # CPU ms of all threads: steadier than wall time on a shared machine
    return float(np.median(ms)), stages
