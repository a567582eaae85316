"""TAA's clipping box from the pixel's own surface (opencl/taa/clip_box.h, Settings.taa_clip_surface, off by
default): on a moving frame the box is built only from the 3x3 neighbours that show the pixel's surface (both
misses, or hits within the view-depth tolerance and the normal angle), the pixel itself always; off, every neighbour
counts. A still scene clips nothing, so its frames are the same either way.

The TAA stage runs once on a hand-made G-buffer (8x6): the left half a surface at depth 2 whose samples are all 1,
the right half another at depth 5 whose samples are all 10. Every pixel reprojects onto itself with history n = 4
(blend weight 1/5). The history of the pixels beside the edge is 5.5: a history blurred across it, as the bilinear
fetch leaves under motion."""

import numpy as np
import pytest
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L

from .taa_step import taa_step

W, H = 8, 6
LEFT, RIGHT, BLURRED = 1.0, 10.0, 5.5


def _buffers() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    g = np.zeros((H, W), L.GSAMPLE)
    depth = np.where(np.arange(W) < W // 2, 2.0, 5.0)[None, :] * np.ones((H, W))
    g["pos"][..., 3] = depth
    g["normal"][..., 2] = 1.0
    g["normal"][..., 3] = L.int_bits(np.zeros((H, W), np.int32))
    g["motion"][..., 2] = 1.0  # a reprojection onto the same pixel ...
    g["motion"][..., 3] = depth  # ... at the same depth: the same surface, so the history is taken
    base = np.where(np.arange(W) < W // 2, LEFT, RIGHT)[None, :, None] * np.ones((H, W, 3))
    history = np.concatenate([base, np.full((H, W, 1), 4.0)], axis=2)
    history[:, W // 2 - 1 : W // 2 + 1, :3] = BLURRED  # the two columns beside the edge
    history[:, 1, :3] = 1.3  # an interior column, away from the edge
    return g, base.astype(np.float32), history.astype(np.float32)


def _taa(clip_surface: bool, moving: bool) -> np.ndarray:
    r = Renderer(scenes.cornell_box(W, H), Settings(taa_clip_surface=clip_surface))
    g, sample, history = _buffers()
    return taa_step(r, g, sample, history, moving)


def test_a_history_blurred_across_an_edge_is_clipped_to_its_own_side():
    on, off = _taa(True, True), _taa(False, True)
    left, right = W // 2 - 1, W // 2
    # the box of the pixel's own surface is its constant colour: the history is clipped to it
    np.testing.assert_allclose(on[:, left, :3], LEFT, rtol=1e-5)
    np.testing.assert_allclose(on[:, right, :3], RIGHT, rtol=1e-5)
    # the negative control: the 3x3 box spans both surfaces and keeps the blurred history (0.2 s + 0.8 h)
    np.testing.assert_allclose(off[:, left, :3], 0.2 * LEFT + 0.8 * BLURRED, rtol=1e-5)
    np.testing.assert_allclose(off[:, right, :3], 0.2 * RIGHT + 0.8 * BLURRED, rtol=1e-5)
    np.testing.assert_array_equal(on[..., 3], off[..., 3])  # the history length does not depend on the box


def test_a_box_within_one_surface_is_unchanged():
    """Away from the edge every neighbour is the pixel's surface: the same box, the same output, bit for bit."""
    on, off = _taa(True, True), _taa(False, True)
    inside = [0, 1, 2, 5, 6, 7]
    np.testing.assert_array_equal(on[:, inside], off[:, inside])
    np.testing.assert_allclose(on[:, 1, :3], LEFT, rtol=1e-5)  # 1.3 clipped to the constant surface


@pytest.mark.parametrize("clip_surface", [True, False])
def test_a_still_scene_clips_nothing(clip_surface):
    out = _taa(clip_surface, False)
    _, sample, history = _buffers()
    want = 0.2 * sample + 0.8 * history[..., :3]
    np.testing.assert_allclose(out[..., :3], want, rtol=1e-6)


def test_still_frames_are_bit_identical():
    """TAA frames of a still camera over a still scene (nothing moves, so TAA clips nothing) are the same with the
    setting on and off, bit for bit."""
    scene = scenes.cornell_box(24, 16)
    imgs = []
    for on in (False, True):
        r = Renderer(scene, Settings(taa_clip_surface=on, seed=3))
        frames = [r.render_frame(0, aovs=False).color for _ in range(3)]
        imgs.append(np.stack(frames))
    np.testing.assert_array_equal(imgs[0], imgs[1])
