"""The real-time filter (opencl/filter/atrous.cl, Settings.realtime_filter): it keeps an edge of a step image where the
G-buffer has one, removes noise on either side, and brings the TAA output of a moving camera closer to each
frame's converged image."""

import numpy as np
import pyopencl as cl
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L

from ..helpers import rel_mse

W, H = 48, 32


def _run_filter(colour: np.ndarray, depth: np.ndarray, noisy: np.ndarray, n: float) -> np.ndarray:
    """The filter stage on a given TAA image (history length n) and 1-sample image, over a flat G-buffer."""
    r = Renderer(scenes.cornell_box(W, H), Settings(realtime_filter=True))
    ctx, q = r.device.context, r.device.queue
    g = np.zeros((H, W), L.GSAMPLE)
    g["pos"][..., 3] = depth
    g["normal"][..., 2] = 1.0
    g["normal"][..., 3] = L.int_bits(np.zeros((H, W), np.int32))  # a hit (primitive 0)
    cl.enqueue_copy(q, r.history.gbuf(r.history.cur), g)
    taa = np.concatenate([colour, np.full((H, W, 1), n)], axis=2).astype(np.float32)
    mf = cl.mem_flags.READ_WRITE | cl.mem_flags.COPY_HOST_PTR
    taa_buf = cl.Buffer(ctx, mf, hostbuf=np.ascontiguousarray(taa))
    cl.enqueue_copy(q, r.buffers.sample, np.concatenate([noisy, np.ones((H, W, 1))], axis=2).astype(np.float32))
    state = type("State", (), {"frame_params": r.frame_params()})()
    out_buf = r.realtime_filter.run(state, taa_buf)
    out = np.empty((H, W, 4), np.float32)
    cl.enqueue_copy(q, out, out_buf)
    return out[..., :3]


def test_the_filter_keeps_a_depth_edge_and_smooths_either_side():
    rng = np.random.default_rng(0)
    left = np.arange(W) < W // 2
    truth = np.where(left[None, :, None], 0.2, 1.0) * np.ones((H, W, 3))
    noisy = truth * rng.gamma(4.0, 0.25, (H, W, 1))  # 1-sample estimates: relative std 0.5
    taa = truth * (1 + 0.5 / 4 * rng.standard_normal((H, W, 1)))  # the mean of about 16 of them
    depth = np.where(left, 2.0, 5.0)[None, :] * np.ones((H, W))
    out = _run_filter(taa, depth, noisy, 16.0)
    inner = (slice(4, H - 4), slice(4, W // 2 - 2)), (slice(4, H - 4), slice(W // 2 + 2, W - 4))
    for sl in inner:
        assert out[sl].std() < 0.5 * taa[sl].std()  # smoother on each side
    # at the edge columns each side keeps its own level: no bleeding across the depth step
    np.testing.assert_allclose(out[4:-4, W // 2 - 1].mean(), 0.2, rtol=0.05)
    np.testing.assert_allclose(out[4:-4, W // 2].mean(), 1.0, rtol=0.05)
    assert np.all(np.isfinite(out))


def test_filtered_moving_frames_are_closer_to_the_reference():
    sc = scenes.many_lights(64, 36, frames=10)
    ref = Renderer(sc, Settings(method="ris", candidates=16, taa=False, seed=7))
    refs = {f: ref.render_still(f, 128).color for f in (6, 9)}
    errs = {}
    for on in (False, True):
        r = Renderer(sc, Settings(seed=3, realtime_filter=on))
        out = {f: r.render_frame(f, aovs=False).color for f in range(10)}
        assert all(np.all(np.isfinite(v)) for v in out.values())
        errs[on] = np.mean([rel_mse(out[f], refs[f]) for f in refs])
    print(f"many_lights 64x36 moving, TAA relMSE frames 6 and 9: {errs[False]:.4f} -> filtered {errs[True]:.4f}")
    # measured 1.13 -> 0.91: the sub-pixel lamps seen directly dominate relMSE here and are kept by the
    # luminance edge stop, so the gain is smaller than on the walls
    assert errs[True] < errs[False], errs
