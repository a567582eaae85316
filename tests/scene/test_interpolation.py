"""Transforms between frames (Scene.at, scene/interpolation.py): a steady turn and slide are where they are at that
time, whole frames are the frames' own matrices, times outside the frames clamp to the first or last."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Scene, translation


def turn(axis: int, angle: float) -> np.ndarray:
    m = np.eye(4)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    c, s = math.cos(angle), math.sin(angle)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def steady(t: float) -> np.ndarray:
    """At frame t: slid by (1, -2, 0.5) a frame, turned 70 degrees a frame about z after a fixed tilt about x,
    scaled from 1 to 3 (uniformly: scale and rotation commute)."""
    s = 1.0 + t
    return translation(t, -2.0 * t, 0.5 * t) @ turn(2, math.radians(70) * t) @ turn(0, 0.4) @ np.diag([s, s, s, 1])


FRAMES = np.stack([steady(0.0), steady(1.0), steady(2.0)])


@pytest.mark.parametrize("t", [0.25, 0.5, 0.9, 1.3, 1.75])
def test_a_steady_motion_is_where_it_is_at_that_time(t):
    assert np.allclose(Scene.at(FRAMES, t), steady(t), atol=1e-9)


def test_whole_frames_are_their_own_matrices_and_the_ends_clamp():
    for f in (0, 1, 2):
        assert np.array_equal(Scene.at(FRAMES, f), FRAMES[f])
        assert np.array_equal(Scene.at(FRAMES, float(f)), FRAMES[f])
    assert np.array_equal(Scene.at(FRAMES, -0.5), FRAMES[0])
    assert np.array_equal(Scene.at(FRAMES, 2.5), FRAMES[2])
    assert np.array_equal(Scene.at(FRAMES[:1], 0.5), FRAMES[0])


def test_a_mirrored_basis_stays_mirrored():
    a = np.diag([-1.0, 1.0, 1.0, 1.0])
    b = turn(2, 0.5) @ a
    m = Scene.at(np.stack([a, b]), 0.5)
    assert np.linalg.det(m[:3, :3]) == pytest.approx(-1.0)
    assert np.allclose(m, turn(2, 0.25) @ a)
