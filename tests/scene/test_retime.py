"""scene_retime: an animation cut into more frames along the same motion."""

import math

import numpy as np
import pytest
from restircl import scenes
from restircl.scene.interpolation import interpolate_transform
from restircl.scene.retime import retime


def _rot_z(a: float, t=(0.0, 0.0, 0.0), s: float = 1.0) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]) * s
    m[:3, 3] = t
    return m


def test_interpolation_is_rotation_slerp_and_linear_translation():
    a, b = _rot_z(0.2, (0, 0, 0), 1.0), _rot_z(1.4, (2, -4, 6), 3.0)
    m = interpolate_transform(a, b, 0.25)
    # a quarter of the way: angle 0.5, translation a quarter, scale linear 1.5
    np.testing.assert_allclose(m, _rot_z(0.5, (0.5, -1.0, 1.5), 1.5), atol=1e-9)
    np.testing.assert_allclose(interpolate_transform(a, b, 0.0), a, atol=1e-9)
    np.testing.assert_allclose(interpolate_transform(a, b, 1.0), b, atol=1e-9)
    # the shorter way round across +-pi
    m = interpolate_transform(_rot_z(3.0), _rot_z(-3.0), 0.5)
    np.testing.assert_allclose(m, _rot_z(math.pi), atol=1e-9)


@pytest.mark.parametrize("angle", [0.1, 1.7, 2.9, -2.5])
def test_interpolation_of_general_rotations(angle):
    """Rotations about every axis survive the quaternion round trip (each branch of the conversion)."""
    rng = np.random.default_rng(7)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    r = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    m = np.eye(4)
    m[:3, :3] = r
    np.testing.assert_allclose(interpolate_transform(np.eye(4), m, 1.0), m, atol=1e-9)
    half = interpolate_transform(np.eye(4), m, 0.5)
    np.testing.assert_allclose(half[:3, :3] @ half[:3, :3], r, atol=1e-9)


def test_retime_keeps_the_original_frames_and_cuts():
    scene = scenes.many_lights(32, 18, frames=5)
    scene.camera.cuts = (3,)
    out = retime(scene, 3)
    assert out.frames == 13
    for f in range(5):
        np.testing.assert_allclose(out.camera.transforms[3 * f], scene.camera.transforms[f], atol=1e-6)
    assert out.camera.cuts == (9,)
    # no motion into a cut: the sub-frames before frame 9 hold frame 6
    np.testing.assert_array_equal(out.camera.transforms[7], out.camera.transforms[6])
    mid = out.camera.transforms[1]
    a, b = scene.camera.transforms[0], scene.camera.transforms[1]
    np.testing.assert_allclose(mid[:3, 3], a[:3, 3] + (b[:3, 3] - a[:3, 3]) / 3, atol=1e-5)
    assert scene.frames == 5  # the original is left as it was
    with pytest.raises(ValueError):
        retime(scene, 0)
