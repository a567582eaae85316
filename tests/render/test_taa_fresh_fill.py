"""TAA's fresh-pixel fill (opencl/taa/fresh_fill.h, Settings.taa_fresh_fill): on a moving camera a pixel without
history shows the mean of the samples of its 3x3 neighbours on its surface (view depth, normal and material within
the reuse's tolerances), itself included; a pixel with history, a miss, and every pixel of a still scene are
untouched. In glossy builds a neighbour of another material (another lobe count, roughness or metallic share:
surface_material_similar) is left out too. The brightest sample counts for no more than the others together, and a
non-finite sample is left out of the mean.

The TAA stage runs once on a hand-made G-buffer (8x6): the left half a surface at depth 2, the right half another at
depth 5; pixel (1, 1) faces another way. Pixels with motion.z = 0 have no reprojection (no history); the others
reproject onto themselves with history n = 4."""

import numpy as np
import pytest
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L

from .taa_step import taa_step

W, H = 8, 6
FRESH = ((2, 2), (3, 3), (0, 0), (5, 1), (6, 4))  # (x, y) without history; (6, 4) is a miss


def _scene_buffers() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    g = np.zeros((H, W), L.GSAMPLE)
    depth = np.where(np.arange(W) < W // 2, 2.0, 5.0)[None, :] * np.ones((H, W))
    g["pos"][..., 3] = depth
    g["normal"][..., 2] = 1.0
    g["normal"][1, 1, :3] = (np.sin(1.0), 0.0, np.cos(1.0))  # 57 degrees away: beyond the 25 of the reuse
    prim = np.zeros((H, W), np.int32)
    prim[4, 6] = -1  # a miss
    g["normal"][..., 3] = L.int_bits(prim)
    g["motion"][..., 2] = 1.0  # a reprojection onto the same pixel ...
    g["motion"][..., 3] = depth  # ... at the same depth: the same surface, so the history is taken
    for x, y in FRESH:
        g["motion"][y, x] = 0.0  # no reprojection: no history
    # samples: the left surface about 1, the right about 10, so that a fill across the edge would show
    rng = np.random.default_rng(5)
    base = np.where(np.arange(W) < W // 2, 1.0, 10.0)[None, :, None]
    sample = (base * rng.uniform(0.5, 1.5, (H, W, 3))).astype(np.float32)
    history = np.concatenate([np.full((H, W, 3), 2.0), np.full((H, W, 1), 4.0)], axis=2).astype(np.float32)
    return g, sample, history


def _taa(fill: bool, moving: bool, glossy: np.ndarray | None = None, sample: np.ndarray | None = None,
         keep_history: bool = True) -> np.ndarray:
    """One TAA step over the hand-made buffers: the colour it shows (rgb) and the history length (w). With
    `glossy`, a glossy build (material_balls) and that G-buffer extension; keep_history False: a reset (a first
    frame, a cut)."""
    scene = scenes.cornell_box(W, H) if glossy is None else scenes.material_balls(W, H)
    r = Renderer(scene, Settings(taa_fresh_fill=fill))
    g, own_sample, history = _scene_buffers()
    sample = own_sample if sample is None else sample
    assert r.flags["HAS_GLOSSY"] == (glossy is not None)
    return taa_step(r, g, sample, history, moving, glossy, keep_history)


def _mean(sample: np.ndarray, pixels: list[tuple[int, int]]) -> np.ndarray:
    return np.mean([sample[y, x] for x, y in pixels], axis=0)


def _luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def test_fresh_pixels_show_their_surfaces_mean():
    _, sample, _ = _scene_buffers()
    on, off = _taa(True, True), _taa(False, True)
    # (2, 2): its 3x3 is all the left surface but (1, 1), which faces another way
    want = _mean(sample, [(1, 2), (1, 3), (2, 1), (2, 2), (2, 3), (3, 1), (3, 2), (3, 3)])
    np.testing.assert_allclose(on[2, 2, :3], want, rtol=1e-5)
    # (3, 3) at the edge: the right surface's column x = 4 is another depth and is left out
    left = [(x, y) for x in (2, 3) for y in (2, 3, 4)]
    np.testing.assert_allclose(on[3, 3, :3], _mean(sample, left), rtol=1e-5)
    across = _mean(sample, [(x, y) for x in (2, 3, 4) for y in (2, 3, 4)])
    assert np.all(np.abs(on[3, 3, :3] - across) > 1.0)  # the negative control: across the edge is far off
    # (0, 0) at the image's corner: the 4 pixels inside the image
    np.testing.assert_allclose(on[0, 0, :3], _mean(sample, [(0, 0), (0, 1), (1, 0)]), rtol=1e-5)
    # (5, 1) inside the right surface: all 9
    want = _mean(sample, [(x, y) for x in (4, 5, 6) for y in (0, 1, 2)])
    np.testing.assert_allclose(on[1, 5, :3], want, rtol=1e-5)
    # a miss keeps its sample; without the fill every fresh pixel shows its own sample
    np.testing.assert_array_equal(on[4, 6, :3], sample[4, 6])
    for x, y in FRESH:
        np.testing.assert_array_equal(off[y, x, :3], sample[y, x])
        assert on[y, x, 3] == 1.0  # the history starts with n = 1 either way
    # pixels with history: the same bits with the fill or without, and they did blend their history
    had = np.ones((H, W), bool)
    for x, y in FRESH:
        had[y, x] = False
    np.testing.assert_array_equal(on[had], off[had])
    assert np.all(on[had][:, 3] == 5.0)


@pytest.mark.parametrize("fill", [True, False])
def test_a_still_scene_is_not_filled(fill):
    _, sample, _ = _scene_buffers()
    out = _taa(fill, False)
    for x, y in FRESH:
        np.testing.assert_array_equal(out[y, x, :3], sample[y, x])


def test_a_neighbour_of_another_material_is_left_out():
    g, sample, _ = _scene_buffers()
    sample[2, 3] = 50.0  # (3, 2): a glossy lobe where its neighbours are diffuse, and far brighter
    glossy = np.zeros((H, W), L.GLOSSY_SAMPLE)
    glossy["wo"][..., :3] = g["normal"][..., :3]
    lobes = np.zeros((H, W), np.int32)
    lobes[2, 3] = 1
    glossy["wo"][..., 3] = L.int_bits(lobes)
    on = _taa(True, True, glossy, sample)
    same = [(1, 2), (1, 3), (2, 1), (2, 2), (2, 3), (3, 1), (3, 3)]  # (2, 2)'s without (1, 1) and (3, 2)
    np.testing.assert_allclose(on[2, 2, :3], _mean(sample, same), rtol=1e-5)
    assert np.all(_mean(sample, [*same, (3, 2)]) > 7.0)  # the negative control: with (3, 2) the fill is far off


def test_a_reset_frame_is_not_filled():
    """A first frame or a camera cut (the plan keeps no history) shows every pixel's own sample, moving or not: the
    fill is for pixels that lost their history to motion, not for a frame that has none."""
    _, sample, _ = _scene_buffers()
    out = _taa(True, True, keep_history=False)
    np.testing.assert_allclose(out[..., :3], sample, rtol=1e-6)
    # the same pixel on a moving frame with history elsewhere is filled (the case above): the reset is what differs
    assert not np.allclose(_taa(True, True)[2, 2, :3], sample[2, 2], rtol=1e-3)


def test_a_firefly_neighbour_is_bounded():
    """One neighbour's sample 10^4 times its surface's: the fresh pixels it reaches show at most twice their other
    samples' mean (the brightest sample counts for no more than all the others together), not a ninth of it."""
    _, sample, _ = _scene_buffers()
    sample[3, 2] = 1e4  # (2, 3): a history pixel in the 3x3 of the fresh (2, 2) and (3, 3)
    on = _taa(True, True, sample=sample)
    for (x, y), same in (((2, 2), [(1, 2), (1, 3), (2, 1), (2, 2), (3, 1), (3, 2), (3, 3)]),
                         ((3, 3), [(2, 2), (2, 4), (3, 2), (3, 3), (3, 4)])):
        others = np.array([sample[v, u] for u, v in same], np.float64)
        rest = _luminance(others).sum()
        # the firefly (grey, so its luminance is 10^4) scaled down to the others' summed luminance, then the mean
        want = (others.sum(axis=0) + rest) / (len(same) + 1)
        np.testing.assert_allclose(on[y, x, :3], want, rtol=1e-5)
        assert _luminance(on[y, x, :3]) <= 2.0 * rest / (len(same) + 1) * (1 + 1e-5)
        assert np.all(_mean(sample, [*same, (2, 3)]) > 1000.0)  # the negative control: the plain mean


def test_a_non_finite_sample_is_left_out_of_the_mean():
    """A NaN sample (the pixel's own, zeroed where it is shown, or a neighbour's) is not counted in the fill's mean,
    as a 0 would darken the pixel; nothing non-finite is written."""
    _, sample, _ = _scene_buffers()
    sample[2, 2] = np.nan  # (2, 2)'s own sample
    sample[4, 3] = np.inf  # (3, 4): a neighbour of (3, 3)
    on = _taa(True, True, sample=sample)
    assert np.all(np.isfinite(on))
    np.testing.assert_allclose(on[2, 2, :3], _mean(sample, [(1, 2), (1, 3), (2, 1), (2, 3), (3, 1), (3, 2), (3, 3)]),
                               rtol=1e-5)
    np.testing.assert_allclose(on[3, 3, :3], _mean(sample, [(2, 3), (2, 4), (3, 2), (3, 3)]), rtol=1e-5)
