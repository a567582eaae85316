"""The distance split of tools/experiments/near_light_spikes.py: the nearest light's distance against values worked
out by hand, and the bands' parts, which together are the frame's relMSE."""

from __future__ import annotations

import numpy as np
import pytest

from tools.experiments import near_light_spikes as tool


def test_nearest_light_by_hand():
    centres = np.array([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0]])
    pos = np.array([[[1.0, 0.0, 0.0], [9.0, 2.0, 0.0]], [[5.0, 0.0, 0.0], [0.0, 0.0, -3.0]]])
    got = tool.nearest_light(pos, centres)
    assert got.shape == (2, 2)
    assert got == pytest.approx(np.array([[1.0, 5**0.5], [5.0, 3.0]]))


def test_nearest_light_over_more_than_one_chunk():
    rng = np.random.default_rng(3)
    centres = rng.uniform(-5, 5, (150, 3))  # three chunks of 64
    pos = rng.uniform(-5, 5, (4, 6, 3))
    brute = np.sqrt(((pos[..., None, :] - centres) ** 2).sum(-1)).min(-1)
    assert tool.nearest_light(pos, centres) == pytest.approx(brute)


def test_bands_add_up_to_the_relmse():
    rng = np.random.default_rng(5)
    frames = {f: {"map": rng.exponential(0.1, (8, 9)), "dist": rng.uniform(0.0, 2.0, (8, 9))} for f in (4, 8)}
    rows = tool.band_table([frames])
    parts = [float(r.split(": ")[1].split(" ")[0]) for r in rows]
    pixels = [float(r.split(") m, ")[1].split(" %")[0]) for r in rows]
    assert len(rows) == len(tool.BANDS) - 1
    assert sum(parts) == pytest.approx(np.mean([v["map"].mean() for v in frames.values()]), abs=1e-3)
    assert sum(pixels) == pytest.approx(100.0, abs=0.3)
