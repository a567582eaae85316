"""eval/nets.py, the (t, k, s)-net check of the Sobol tests and the layout probe, on point sets whose t is worked out
by hand: a grid's cell centres, the 2D Hammersley set (the bit-reversed index beside the index) and a 3D grid."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.eval.nets import net_holds, t_value

CENTRES = (np.arange(16) + 0.5) / 16 * 2.0**32  # the centres of 16 intervals of [0, 1), as 32-bit fractions


def test_a_grid_holds_its_boxes_and_no_finer():
    # a 4 x 4 grid's cell centres (1/8, 3/8, 5/8, 7/8 in each coordinate): every box of volume 1/4 (1 x 1/4,
    # 1/2 x 1/2, 1/4 x 1) holds 4; a box 1/8 wide holds a whole grid column or nothing: t = 2, not 1
    g = CENTRES[::4]
    grid = np.column_stack([np.repeat(g, 4), np.tile(g, 4)]).astype(np.uint32)
    assert net_holds(grid, 4, 2) and not net_holds(grid, 4, 1)
    assert t_value(grid, 4) == 2


def test_hammersley_is_a_zero_net():
    # x = (i + 1/2) / 16, y = the bit reversal of i over 4 bits (+ half a cell): one point per elementary interval
    reversed_bits = [int(f"{i:04b}"[::-1], 2) * 2**28 + 2**27 for i in range(16)]
    hammersley = np.column_stack([CENTRES, reversed_bits]).astype(np.uint32)
    assert net_holds(hammersley, 4, 0) and t_value(hammersley, 4) == 0
    moved = hammersley.copy()  # point 0's x moved into point 1's sixteenth: that interval holds 2, the first none
    moved[0, 0] = moved[1, 0]
    assert not net_holds(moved, 4, 0) and net_holds(moved, 4, 1)


def test_a_3d_grid_holds_only_halves():
    # 2 x 2 x 2 centres (1/4, 3/4 in each coordinate): 4 in each half of one coordinate (t = 2, boxes of volume 1/2);
    # the quarters of one coordinate are half empty (t = 1 fails), so are the eighths (t = 0)
    c = np.array([0.25, 0.75]) * 2.0**32
    grid = np.array([[x, y, z] for x in c for y in c for z in c]).astype(np.uint32)
    assert [net_holds(grid, 3, t) for t in range(4)] == [False, False, True, True]
    assert t_value(grid, 3) == 2


def test_the_point_count_must_be_two_to_the_k():
    with pytest.raises(ValueError):
        net_holds(np.zeros((15, 2), np.uint32), 4, 0)
