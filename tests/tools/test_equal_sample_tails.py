"""The tail counts of tools/experiments/equal_sample_tails.py against values worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from tools.experiments import equal_sample_tails as tool


def test_tail_counts_as_worked_out():
    # 2 seeds of a 2 x 2 image of reference 0.9 (ratio base 0.9 + 0.1 = 1): material 0 on the top row, 1 below, the
    # bottom-right pixel no surface. Seed 0: top-left 50 (a sample above 10x and 30x, not 100x); seed 1: bottom-left
    # 200 (above all three); every other sample exact. relMSE terms (x - 0.9)^2 / 0.82: seed 0's holds 49.1^2, seed
    # 1's 199.1^2, so material 1 holds 199.1^2 / (49.1^2 + 199.1^2) of the sum and the no-surface pixel none.
    ref = np.full((2, 2, 3), 0.9)
    imgs = np.stack([ref.copy(), ref.copy()])
    imgs[0, 0, 0] = 50.0
    imgs[1, 1, 0] = 200.0
    mats = np.array([[0, 0], [1, -1]])
    got = tool.tail_counts(imgs, ref, mats, 2)
    assert got["counts"] == {0: [1, 1, 0], 1: [1, 1, 1], -1: [0, 0, 0]}
    a, b = 49.1**2, 199.1**2
    assert got["share"][1] == pytest.approx(b / (a + b), rel=1e-12)
    assert got["share"][-1] == 0.0
    assert got["per_seed"] == pytest.approx([a / 0.82 / 4, b / 0.82 / 4], rel=1e-12)


def test_a_material_without_pixels_is_left_out():
    ref = np.full((1, 2, 3), 0.4)
    got = tool.tail_counts(np.stack([ref]), ref, np.array([[0, 0]]), 3)
    assert set(got["counts"]) == {0}
