"""The times of a still's samples within the shutter (render/shutter.py): they fill the shutter evenly, each half
buffer its own way, and without motion blur every sample is at the frame itself; an animation frame's time, the
shutter TAA gathers over, and the cameras' times of the frame's plan."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.render.plan import FrameSituation, plan_frame
from restircl.render.shutter import ShutterTimes, at_phase, frame_phase, shifted, sweep
from restircl.scene.camera import Camera
from restircl.settings.table import Settings


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


def test_animation_frames_take_stratified_times_of_their_shutter():
    """One time per frame over the sample index: any 25 consecutive frames fill the shutter's fifths and 25ths."""
    cam = Camera(np.eye(4), 8, 8, shutter=(-0.5, 0.5))
    phases = np.array([frame_phase(cam, 3, sample, seed=1) for sample in range(40, 165)])
    assert np.all((phases >= -0.5) & (phases < 0.5))
    for bins in (5, 25):
        counts = np.histogram(phases, bins=bins, range=(-0.5, 0.5))[0]
        assert np.all(np.abs(counts - 125 // bins) <= 1), counts
    for start in range(40, 140, 25):  # each run of 5 frames covers the 5 fifths once
        fifths = np.floor((phases[start - 40:start - 35] + 0.5) * 5)
        assert sorted(fifths) == [0, 1, 2, 3, 4]
    assert frame_phase(Camera(np.eye(4), 8, 8), 3, 7, seed=1) == 0.0  # no motion blur: the frame itself
    assert frame_phase(None, 3, 7, seed=1) == 0.0


def test_a_frame_at_its_phase_sees_its_shutter_around_it_and_reprojects_at_the_same_phase():
    cam = Camera(np.eye(4), 8, 8, shutter=(-0.25, 0.25))
    assert sweep(cam, 0.1, still=False) == pytest.approx((-0.35, 0.15))
    assert sweep(cam, 0.1, still=True) == (0.0, 0.0)  # a still averages its samples instead
    assert sweep(Camera(np.eye(4), 8, 8), 0.0, still=False) == (0.0, 0.0)
    plan = plan_frame(Settings(), FrameSituation(frame=4, last_frame=3, frame_count=9, history_valid=True))
    moved = at_phase(plan, -0.2)
    assert (moved.frame, moved.prev_frame, moved.next_frame) == pytest.approx((3.8, 2.8, 4.8))
    assert at_phase(plan, 0.0) is plan
    assert shifted(None, 0.3) is None and shifted(5, 0.0) == 5 and isinstance(shifted(5, 0.0), int)
    assert shifted(5, -0.25) == 4.75
