"""The visibility shortcut of the temporal reuse (Settings.visibility_max_age, restir/reuse.h VisKnown): where last
frame's point is this pixel's, the stored shadow tests answer exactly what the rays would, so the frames are the
unbiased mode's bit for bit; where anything moves it is not taken at all; at a distance it is taken (and is then
an approximation)."""

import numpy as np
import pyopencl as cl
from restircl import Light, Renderer, Settings, translation
from restircl.core import layouts as L

from ..helpers import occluder_scene

W, H = 16, 12
FRAMES = 8
SAME_POINT = dict(visibility_max_age=64, visibility_max_distance=1e-3)


def render(scene, settings: Settings, still: bool) -> tuple[np.ndarray, int]:
    """The noisy frames, and the largest Reservoir.vis_age left in the history (> 0: the shortcut was taken)."""
    r = Renderer(scene, settings)
    frames = np.stack([r.render_frame(0 if still else f, still=still).noisy for f in range(FRAMES)])
    age = 0
    for slot in (0, 1):
        res = np.empty(r.pixels, L.RESERVOIR)
        cl.enqueue_copy(r.device.queue, res, r.history.reservoirs(slot))
        age = max(age, int(res["vis_age"].max()))
    return frames, age


def test_shortcut_at_the_same_point_gives_the_traced_frames():
    """A still camera without jitter or permutation: the history's point is the pixel's own, bit for bit."""
    scene = occluder_scene(W, H)
    base = dict(method="restir", jitter=False, taa=False, seed=5, temporal_permutation=False)
    traced, age0 = render(scene, Settings(**base), still=True)
    shortcut, age = render(scene, Settings(**base, **SAME_POINT), still=True)
    assert age0 == 0 and age > 0  # the shortcut was taken
    np.testing.assert_array_equal(shortcut, traced)


def test_shortcut_is_not_taken_when_a_light_moves():
    scene = occluder_scene(W, H)
    moving = Light("moving", "point", (1.0, 1.0, 1.0), 50.0,
                   np.stack([translation(0.2 * f - 0.7, 0.0, 1.2) for f in range(FRAMES)]), radius=0.05)
    scene.lights = [moving, *scene.lights[1:]]
    scene = scene.validate()
    base = dict(method="restir", jitter=False, taa=False, seed=6, temporal_permutation=False)
    traced, _ = render(scene, Settings(**base), still=False)
    shortcut, age = render(scene, Settings(**base, visibility_max_age=64, visibility_max_distance=16.0), still=False)
    assert age == 0
    np.testing.assert_array_equal(shortcut, traced)


def test_shortcut_within_a_distance_is_taken_and_bounded_by_the_age():
    """Sub-pixel jitter puts last frame's point up to a pixel off: with a distance of 8 the shortcut is taken, and no
    reservoir reuses a stored visibility more than max_age times in a row."""
    scene = occluder_scene(W, H)
    s = Settings(method="restir", taa=False, seed=7, jitter=True, temporal_permutation=False, visibility_max_age=3,
                 visibility_max_distance=8.0)
    frames, age = render(scene, s, still=True)
    assert np.all(np.isfinite(frames))
    assert age == 3
