"""The error split of tools/experiments/first_frame_error.py against values worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from tools.experiments import first_frame_error as tool


def test_error_split_as_worked_out():
    # 10 pixels of reference 1 (weight 1 / 1.01); one pixel off by 3 (error 9 / 1.01), one by 1 (1 / 1.01), the rest
    # exact: relMSE 10 / 1.01 / 10, the 5 worst hold all of it, the pixel off by 3 is the only one whose path light
    # (4) exceeds the reference, and it holds 9 / 10
    ref = np.ones((2, 5, 3))
    img = ref.copy()
    img[0, 0] += 3.0
    img[1, 2] += 1.0
    path = np.zeros_like(ref)
    path[0, 0] = 4.0
    path[1, 2] = 1.0  # equal to the reference: not above it
    got = tool.error_split(img, ref, path)
    assert got["rel_mse"] == pytest.approx(1.0 / 1.01, rel=1e-12)
    assert got["worst5"] == pytest.approx(1.0, rel=1e-12)
    assert got["path_heavy"] == pytest.approx(0.9, rel=1e-12)
    assert got["path_heavy_pixels"] == 1


def test_error_split_of_an_exact_image_is_zero():
    ref = np.full((3, 4, 3), 0.5)
    got = tool.error_split(ref.copy(), ref, np.zeros_like(ref))
    assert got == {"rel_mse": 0.0, "worst5": 0.0, "worst50": 0.0, "path_heavy": 0.0, "path_heavy_pixels": 0}


def test_seeds_as_a_range_or_a_list():
    assert tool.seeds_of("1000-1003") == [1000, 1001, 1002, 1003]
    assert tool.seeds_of("5,9") == [5, 9]
