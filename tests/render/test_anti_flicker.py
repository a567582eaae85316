"""ReSTIR's anti-flicker options: the boiling filter (opencl/restir/boiling.cl, Settings.boiling_filter) and
permutation sampling (camera/reproject.h, Settings.temporal_permutation; its unbiasedness:
tests/render/test_restir.py)."""

from __future__ import annotations

import numpy as np
import pyopencl as cl
import pytest
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L
from restircl.eval.probe_defines import add_probe_defines
from restircl.render.stages import permutation_key


def _filtered(res: np.ndarray, strength: float, mode: str = "weight") -> np.ndarray:
    h, w = res.shape
    r = Renderer(scenes.cornell_box(w, h), Settings(boiling_filter=strength, boiling_mode=mode))
    ctx, q = r.device.context, r.device.queue
    buf = cl.Buffer(ctx, cl.mem_flags.READ_WRITE | cl.mem_flags.COPY_HOST_PTR, hostbuf=res)
    state = type("State", (), {"frame_params": r.frame_params()})()
    r.boiling.run(state, buf)
    out = np.empty_like(res)
    cl.enqueue_copy(q, out, buf)
    return out


def _reservoirs(h: int = 16, w: int = 24) -> np.ndarray:
    res = np.zeros((h, w), L.RESERVOIR)
    res["light"] = 0
    res["u"], res["v"] = 0.25, 0.5
    res["M"] = 8.0
    res["target"] = 1.0
    res["W"] = np.random.default_rng(0).uniform(0.5, 1.5, (h, w))
    return res


def test_an_injected_outlier_is_removed_and_ordinary_reservoirs_are_not():
    """Strength 0.2 (RTXDI's default) empties what is above 41 times the mean of the others in its 8x8 tile."""
    res = _reservoirs()
    res["W"][3, 4] = 500.0  # 500 > 41 x ~1
    res["W"][11, 20] = 20.0  # a bright but ordinary sample: kept
    res["light"][12, 2] = -1  # an empty one stays empty and is not counted
    res["W"][12, 2] = 0.0
    out = _filtered(res, 0.2)
    assert out["light"][3, 4] == -1 and out["W"][3, 4] == 0 and out["M"][3, 4] == 0
    keep = np.ones(res.shape, bool)
    keep[3, 4] = False
    np.testing.assert_array_equal(out[keep], res[keep])


def test_strength_sets_the_threshold():
    """Strength 1: anything above the mean of the others goes (threshold 10 / 1 - 9 = 1); 20 x the mean survives
    strength 0.2 but not 0.5 (threshold 11)."""
    res = _reservoirs()
    res["W"][:] = 1.0
    res["W"][11, 20] = 20.0
    assert _filtered(res, 0.2)["light"][11, 20] == 0
    assert _filtered(res, 0.5)["light"][11, 20] == -1
    res["W"][11, 20] = 1.5
    out = _filtered(res, 1.0)
    assert out["light"][11, 20] == -1 and np.sum(out["light"] == -1) == 1


def test_the_contribution_mode_removes_a_held_bright_sample_of_ordinary_weight():
    """The blotches of many_lights' still camera (tools/experiments/boiling_probe.py): a sample of a light close to
    the pixel, found by a lucky candidate and then held in the pixel's temporal chain for ~20 frames. Its target is
    large and its W below its tile's mean (median W / mean 0.05), so RTXDI's weight test keeps it; what stands out
    is what it adds to its pixel, target x W (median 2.4x the neighbourhood's median while held, p90 20x). The
    contribution mode at strength 0.7 (threshold 10 / 0.7 - 9 = 5.3) empties it; an ordinary pixel, and one whose W
    alone is high but whose contribution is not, stay."""
    res = _reservoirs()
    res["target"][3, 4], res["W"][3, 4] = 60.0, 0.5  # contribution 30 against ~1 around it, W below the mean
    res["target"][11, 20], res["W"][11, 20] = 0.02, 50.0  # W 50x the mean, contribution 1: ordinary
    res["target"][5, 9], res["W"][5, 9] = 4.0, 1.0  # a brighter pixel, contribution ~4 (< 5.3 x the mean): kept
    by_weight = _filtered(res, 0.7, "weight")
    assert by_weight["light"][3, 4] == 0  # the weight test does not see it ...
    assert by_weight["light"][11, 20] == -1  # ... and takes the ordinary one
    out = _filtered(res, 0.7, "contribution")
    assert out["light"][3, 4] == -1 and out["W"][3, 4] == 0 and out["M"][3, 4] == 0
    keep = np.ones(res.shape, bool)
    keep[3, 4] = False
    np.testing.assert_array_equal(out[keep], res[keep])


def test_forget_keeps_the_held_sample_but_drops_its_history_weight():
    """Mode forget: the same outlier keeps its sample and W (its energy stays in this frame) and its M drops to 1,
    so that the temporal chain lets go of it; every other reservoir is left as it is."""
    res = _reservoirs()
    res["target"][3, 4], res["W"][3, 4], res["M"][3, 4] = 60.0, 0.5, 160.0
    out = _filtered(res, 0.7, "forget")
    assert out["M"][3, 4] == 1.0
    for k in ("light", "u", "v", "W", "target", "w_sum"):
        assert out[k][3, 4] == res[k][3, 4], k
    keep = np.ones(res.shape, bool)
    keep[3, 4] = False
    np.testing.assert_array_equal(out[keep], res[keep])


@pytest.mark.parametrize("strength", [0.0, 0.2])
def test_still_renders_never_filter_and_animations_stay_finite(strength):
    sc = scenes.many_lights(40, 24, frames=4)
    base = Renderer(sc, Settings(seed=3)).render_still(0, 4).color
    still = Renderer(sc, Settings(seed=3, boiling_filter=strength)).render_still(0, 4).color
    np.testing.assert_array_equal(still, base)
    r = Renderer(sc, Settings(seed=3, boiling_filter=strength))
    for f in range(4):
        assert np.all(np.isfinite(r.render_frame(f, aovs=False).color))


def test_permutation_sampling_takes_a_neighbours_history():
    """The key changes from frame to frame and the images change with it (still camera, no jitter: without the
    permutation every pixel reuses its own history)."""
    sc = scenes.many_lights(32, 20, frames=1)
    imgs = []
    for perm in (False, True):
        r = Renderer(sc, Settings(seed=2, jitter=False, temporal_permutation=perm))
        imgs.append([r.render_frame(0, aovs=False).color for _ in range(3)])
    np.testing.assert_array_equal(imgs[0][0], imgs[1][0])  # no history yet: the same first frame
    assert not np.array_equal(imgs[0][2], imgs[1][2])
    keys = {permutation_key(r.settings, type("S", (), {"frame_params": {"sample": k, "seed": 2}})()) for k in range(64)}
    assert len(keys) == 16 and all(16 <= k < 32 for k in keys)


def test_permutation_second_try_only_adds_histories(monkeypatch):
    """Where the permuted pixel fails the surface test the block's second bijection is tried (camera/reproject.h).
    A still camera without jitter gives both builds the same G-buffers and keys, so every pixel that finds a
    history with the first bijection alone (the probe PROBE_PERMUTATION_ONE_TRY, the control) finds one with both,
    and the lamps' edges in the blocks leave some that only the second try gives one."""
    sc = scenes.many_lights(48, 32, frames=1)

    def with_history(defines: list[str]) -> np.ndarray:
        with monkeypatch.context() as m:
            add_probe_defines(defines, m.setattr)
            r = Renderer(sc, Settings(seed=2, jitter=False))
            for _ in range(4):
                r.render_frame(0, aovs=False)
            temp = np.empty(r.pixels, L.RESERVOIR)
            cl.enqueue_copy(r.device.queue, temp, r.buffers.res_temp)
            r.device.queue.finish()
            return temp["M"] > r.settings.candidates + r.last_plan.bsdf_candidates  # more than this frame's own

    one, both = with_history(["PROBE_PERMUTATION_ONE_TRY"]), with_history([])
    assert np.all(both[one])
    assert both.sum() > one.sum(), (both.sum(), one.sum())


def test_disocclusion_boost_is_taken_only_without_history():
    """Spatial-only reuse: no pixel has history, each takes 8 neighbours, so the image changes; with a boost not
    above Neighbours (3) nothing changes. (Its worth, measured on the first frame of a 48x36 cornell box, paired
    seeds: error x 0.96 +- 0.04 with 8 neighbours; unbiasedness: tests/render/test_restir.py.)"""
    sc = scenes.cornell_box(32, 24)

    def frame(boost: int) -> np.ndarray:
        return (
            Renderer(sc, Settings(seed=2, temporal=False, spatial_neighbours=3, disocclusion_boost=boost))
            .render_frame(0)
            .color
        )

    base = frame(0)
    assert not np.array_equal(frame(8), base)
    np.testing.assert_array_equal(frame(3), base)
