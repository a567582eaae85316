"""The extra candidates of a lonely fresh pixel (Settings.fresh_candidates, restir/lonely_fresh.h): a pixel without
temporal history that no spatial neighbour is similar to merges K more candidates of its own, and its M grows by
them (K light and the sampler's BSDF candidates); a pixel with history, or with a similar neighbour, gets none.
Unbiasedness: render/test_restir.py."""

import numpy as np
import pyopencl as cl
from restircl import Renderer, Settings
from restircl.core import layouts as L

from ..helpers import occluder_scene

W, H = 16, 12
K = 5
PER_FRAME = 8  # the M of an initial reservoir: 8 candidates (a diffuse scene: no BSDF candidates by default)


def m_after(settings: Settings, frames: int) -> np.ndarray:
    """The M of every pixel's final reservoir after `frames` frames of a still camera."""
    r = Renderer(occluder_scene(W, H), settings)
    for f in range(frames):
        r.render_frame(f)
    res = np.empty(r.pixels, L.RESERVOIR)
    cl.enqueue_copy(r.device.queue, res, r.history.reservoirs(r.history.prev))  # the frame just ended
    return res["M"]


def test_a_lonely_fresh_pixel_gets_k_more_candidates_and_others_none():
    """Spatial only (every pixel fresh), one neighbour, no boost: a pixel whose neighbour is similar merges it
    (M 8 + 8 = 16), with K = 0 or 5 alike; a lonely one keeps M 8 with K = 0 and has 8 + 5 = 13 with K = 5."""
    s = dict(method="restir", jitter=False, taa=False, seed=3, temporal=False, spatial_neighbours=1,
             disocclusion_boost=0)
    off = m_after(Settings(**s, fresh_candidates=0), 1)
    on = m_after(Settings(**s, fresh_candidates=K), 1)
    valid = off > 0
    lonely = valid & (off == PER_FRAME)
    assert set(np.unique(off[valid])) <= {PER_FRAME, 2 * PER_FRAME}
    assert 0 < lonely.sum() < valid.sum()  # both kinds are in the image
    np.testing.assert_array_equal(on[lonely], PER_FRAME + K)
    np.testing.assert_array_equal(on[~lonely], off[~lonely])


def test_a_pixel_with_history_gets_none():
    """Frame 1 of a still camera with a history cap of one frame's M: a pixel with history has M 8 + 8 after the
    temporal pass, whatever its frame 0 had (13 or 16 with K = 5), then 16, 24 or 32 after the spatial pass, and
    keeps the M of K = 0's render; only pixels the reprojection found no history for may differ. Without
    permutation sampling, so that (nearly) every pixel finds its own history: a permuted neighbour across an edge
    leaves a pixel without one, which is the other test's case."""
    s = dict(method="restir", jitter=False, taa=False, seed=4, spatial_neighbours=1, disocclusion_boost=0,
             m_cap=1.0, temporal_permutation=False)
    off = m_after(Settings(**s, fresh_candidates=0), 2)
    on = m_after(Settings(**s, fresh_candidates=K), 2)
    history = off >= 2 * PER_FRAME
    assert history.sum() >= 0.9 * (off > 0).sum()
    assert set(np.unique(off[history])) <= {2 * PER_FRAME, 3 * PER_FRAME, 4 * PER_FRAME}
    np.testing.assert_array_equal(on[history], off[history])
