"""The scenes of ReSTIR in motion (restircl/eval/scenes/motion_validation.py): the validation orbit shows the
validation market's lights from a camera circling its centre at 15 m out, 7 m up and 1 degree per frame."""

from __future__ import annotations

import math

import numpy as np
from restircl.eval.scenes.motion_validation import MOTION_SCENES, motion_scene


def test_market_orbit_circles_the_market():
    orbit, lane = motion_scene("market_orbit", 32, 18, 6), motion_scene("market_validation", 32, 18, 6)
    assert set(MOTION_SCENES) >= {"garden_orbit", "market_validation", "market_orbit"}
    assert orbit.name == "market_orbit" and len(orbit.lights) == len(lane.lights) == 420
    eyes = orbit.camera.transforms[:, :3, 3]
    assert eyes.shape == (6, 3)
    np.testing.assert_allclose(np.hypot(eyes[:, 0], eyes[:, 1]), 15.0, rtol=1e-9)
    np.testing.assert_allclose(eyes[:, 2], 7.0)
    angles = np.degrees(np.unwrap(np.arctan2(eyes[:, 1], eyes[:, 0])))
    np.testing.assert_allclose(np.diff(angles), 1.0, rtol=1e-6)
    assert math.isclose(angles[0], -70.0, abs_tol=1e-9)
