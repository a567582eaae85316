"""The times of a still's samples within the shutter (render/shutter.py): they fill the shutter evenly, each half
buffer its own way, and without motion blur every sample is at the frame itself."""

from __future__ import annotations

import numpy as np
from restircl.render.shutter import ShutterTimes


def test_shutter_times_fill_the_shutter_evenly_per_half():
    times = ShutterTimes((-0.25, 0.25), seed=3)
    got = {h: np.array([times.time(7, h) for _ in range(125)]) for h in (0, 1)}
    for t in got.values():
        assert np.all((t >= 7 - 0.25) & (t < 7 + 0.25))
        # stratified in base 5: each fifth and each 25th of the shutter holds its share of the 125 times, +-1
        for bins in (5, 25):
            counts = np.histogram(t, bins=bins, range=(6.75, 7.25))[0]
            assert np.all(np.abs(counts - 125 // bins) <= 1), counts
    assert not np.allclose(got[0], got[1])  # the halves are shifted apart
    assert ShutterTimes((0.0, 0.0), 3).time(7, 0) == 7  # no blur: the frame itself
