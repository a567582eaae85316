"""Motion blur of still renders: each sample of a still is the scene at its own time within the open shutter
(Camera.shutter, frames from the rendered frame), so that the average over the samples is the image integrated
over the shutter, as Cycles' is. The whole image of one sample shares its time: the camera, the objects and the
lights are where they are then (Scene.at between frames, scene/interpolation.py), and the geometry and its BVH are
uploaded again for every sample where objects move within the shutter (render/pipeline.py does so whenever the
frame changes).

The times: a van der Corput sequence in base 5 (the jitter takes bases 2 and 3), randomly shifted per half buffer
of the still, as its jitter is, so that each half stays an independent estimate of the blurred pixel."""

from __future__ import annotations

import numpy as np

from .camera import halton


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
