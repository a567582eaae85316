"""The spread of lights of tools/experiments/tree_spread.py (the relative second moment of drawing a light by its
power for the light that reaches the lights' own centres), against values worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from tools.experiments import tree_spread as tool


def test_lights_at_one_point_need_no_tree():
    # every light equally far from every probe: power is the right proposal, m = 1
    assert tool.light_spread(np.zeros((50, 3)), np.linspace(1, 5, 50)) == pytest.approx(1.0)


def test_equal_lights_far_apart_give_their_count():
    # 40 equal lights 1 km apart on a line: at each centre its own light brings 1 / FLOOR^2, the others nothing
    # to speak of, so m = N x (1 / FLOOR^4) / (1 / FLOOR^2)^2 = N
    c = np.zeros((40, 3))
    c[:, 0] = np.arange(40) * 1000.0
    assert tool.light_spread(c, np.ones(40)) == pytest.approx(40.0, rel=1e-4)


def test_two_lights_as_worked_out():
    # two equal lights D apart: at either centre e = FLOOR^2 / (D^2 + FLOOR^2) is the other's share of the own
    # light's, and m = 2 (1 + e^2) / (1 + e)^2
    d = 1.5
    e = tool.FLOOR**2 / (d * d + tool.FLOOR**2)
    want = 2 * (1 + e * e) / (1 + e) ** 2
    assert tool.light_spread([[0, 0, 0], [d, 0, 0]], [3.0, 3.0]) == pytest.approx(want, rel=1e-12)


def test_dark_and_missing_lights_are_left_out():
    assert tool.light_spread([[0, 0, 0]], [1.0]) == 1.0
    assert tool.light_spread([[0, 0, 0], [1e3, 0, 0], [np.nan, 0, 0]], [1.0, 0.0, 1.0]) == 1.0


def test_lamp_fields_spread_with_their_side():
    # the same 400 lamps over a 10 m and a 200 m square: packed, a lamp's surroundings see many; spread, one
    dense, wide = (tool.lamp_field(400, side, 16, 9) for side in (10.0, 200.0))
    spreads = [tool.light_spread(tool.scene_light_positions(s), np.array([lt.power for lt in s.lights]))
               for s in (dense, wide)]
    assert len(dense.lights) == 400 and spreads[0] < 10 < 100 < spreads[1]
