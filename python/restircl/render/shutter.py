"""Motion blur. Still renders: each sample of a still is the scene at its own time within the open shutter
(Camera.shutter, frames from the rendered frame), so that the average over the samples is the image integrated
over the shutter, as Cycles' is. The whole image of one sample shares its time: the camera, the objects and the
lights are where they are then (Scene.at between frames, scene/interpolation.py), and the geometry and its BVH are
uploaded again for every sample where objects move within the shutter (render/pipeline.py does so whenever the
frame changes).

The times: a van der Corput sequence in base 5 (the jitter takes bases 2 and 3), randomly shifted per half buffer
of the still, as its jitter is, so that each half stays an independent estimate of the blurred pixel.

Animation and viewport frames (one sample per pixel, accumulated by TAA) take one time each from the same sequence
over their sample index (frame_phase), so that the frames TAA averages cover the shutter evenly; what their
reprojection and reuse make of it: docs/design.md, "Depth of field and motion blur in motion"."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..scene.camera import Camera
from .camera import halton
from .plan import FramePlan


class ShutterTimes:
    """The times of a still's samples, per half buffer."""

    def __init__(self, shutter: tuple[float, float], seed: int) -> None:
        self.open, self.close = (float(t) for t in shutter)
        self.counts = [0, 0]
        self.shifts = np.random.default_rng([seed, 0x5107]).random(2)

    @property
    def blurs(self) -> bool:
        return self.close > self.open

    def time(self, frame: int, half: int) -> float:
        """The time of the next sample of `half`: `frame` itself without motion blur."""
        if not self.blurs:
            return frame
        i = self.counts[half] = self.counts[half] + 1
        u = (halton(i, 5) + float(self.shifts[half])) % 1.0
        return frame + self.open + (self.close - self.open) * u


def frame_phase(camera: Camera | None, frame: int, sample: int, seed: int) -> float:
    """Where in its shutter animation frame `frame` (random stream key `sample`) is rendered, in frames from
    `frame`: 0 without motion blur, else a point of the shutter (base-5 van der Corput over the sample index,
    shifted by the seed), so that consecutive frames cover the shutter evenly."""
    a, b = camera.shutter if camera is not None else (0.0, 0.0)
    if not b > a:
        return 0.0
    shift = float(np.random.default_rng([seed, 0x5108]).random())
    return a + (b - a) * ((halton(sample % 3125 + 1, 5) + shift) % 1.0)


def shifted(frame: int | None, phase: float) -> float | None:
    """`frame` at `phase` of its shutter; `frame` itself (an int, or None) without motion blur."""
    return frame + phase if phase and frame is not None else frame


def sweep(camera: Camera | None, phase: float, still: bool) -> tuple[float, float]:
    """The shutter of an animation frame rendered at `phase` (frame_phase), in frames from its time: what TAA's
    history gathers over (taa/sweep.h); (0, 0): a sharp frame, or a still's (which averages instead)."""
    a, b = camera.shutter if camera is not None else (0.0, 0.0)
    return (0.0, 0.0) if still or not b > a else (a - phase, b - phase)


def at_phase(plan: FramePlan, phase: float) -> FramePlan:
    """`plan` with its camera and Vector-pass times at `phase` of their frames' shutters: this frame's, and the
    previous and next frames' at the same point of theirs (the reprojection's rule, docs/design.md)."""
    if not phase:
        return plan
    return replace(plan, frame=plan.frame + phase, prev_frame=plan.prev_frame + phase,
                   next_frame=plan.next_frame + phase)
