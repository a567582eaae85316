"""eval/metrics.py's relMSE and its per-pixel map against values worked out by hand: each pixel's term is the mean over
its colour channels of (x - r)^2 / (r^2 + 0.01), alpha left out, and rel_mse is the mean of the map."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.eval.metrics import rel_mse, rel_mse_map


def test_the_map_is_each_pixels_term():
    # reference 1 everywhere (weight 1 / 1.01); pixel (0, 0) off by 2 in one channel of three: 4 / 1.01 / 3; pixel
    # (1, 2) off by 0.5 in all three: 0.25 / 1.01
    ref = np.ones((2, 3, 3))
    img = ref.copy()
    img[0, 0, 1] += 2.0
    img[1, 2] -= 0.5
    got = rel_mse_map(img, ref)
    assert got.shape == (2, 3) and got.dtype == np.float64
    assert got[0, 0] == pytest.approx(4.0 / 1.01 / 3.0, rel=1e-12)
    assert got[1, 2] == pytest.approx(0.25 / 1.01, rel=1e-12)
    assert got.sum() == pytest.approx(4.0 / 1.01 / 3.0 + 0.25 / 1.01, rel=1e-12)  # the rest is 0
    assert rel_mse(img, ref) == pytest.approx((4.0 / 1.01 / 3.0 + 0.25 / 1.01) / 6.0, rel=1e-12)


def test_dark_pixels_are_weighed_by_the_offset():
    # reference 0: the weight is 1 / 0.01, so an error of 0.1 gives 1
    assert rel_mse_map(np.full((1, 1, 3), 0.1), np.zeros((1, 1, 3)))[0, 0] == pytest.approx(1.0, rel=1e-12)


def test_alpha_is_left_out_and_float32_images_are_taken_in_float64():
    # RGBA float32 images: alpha differs wildly and does not count; 0.1 is not a float32, its error is taken as
    # float32(0.1)'s: (float32(1.1) - 1)^2 / 1.01 in one channel of three
    ref = np.ones((1, 2, 4), np.float32)
    img = ref.copy()
    img[..., 3] = 50.0
    img[0, 1, 0] = np.float32(1.1)
    got = rel_mse_map(img, ref)
    assert got[0, 0] == 0.0
    assert got[0, 1] == pytest.approx((float(np.float32(1.1)) - 1.0) ** 2 / 1.01 / 3.0, rel=1e-12)
