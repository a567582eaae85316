"""The pixel ranking of tools/experiments/worst_pixels.py, against maps and values written out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from tools.experiments import worst_pixels as tool


def test_the_largest_terms_of_all_frames_first():
    a = np.array([[0.0, 5.0], [1.0, 0.5]])
    b = np.array([[3.0, 0.0], [0.0, 9.0]])
    assert tool.worst({4: a, 8: b}, 3) == [(8, 1, 1, 9.0), (4, 0, 1, 5.0), (8, 0, 0, 3.0)]


def test_the_seed_without_one_pixel():
    # frame 4's mean is (0 + 5 + 1 + 0.5) / 4 = 1.625, frame 8's (3 + 9) / 4 = 3; without frame 8's 9: 0.75
    a = np.array([[0.0, 5.0], [1.0, 0.5]])
    b = np.array([[3.0, 0.0], [0.0, 9.0]])
    assert tool.without({4: a, 8: b}, 8, 1, 1) == pytest.approx((1.625 + 0.75) / 2)
    assert tool.without({4: a, 8: b}, 4, 0, 1) == pytest.approx((0.375 + 3.0) / 2)


def test_the_reservoir_record_is_the_kernels():
    assert tool.RESERVOIR.itemsize == 32  # opencl/types.h Reservoir
