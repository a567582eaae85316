"""tools/experiments/taa_floor.py: its TAA stage with the input or the history replaced, on a small orbit whose
replacements are flat colours (TAA of flat colours is known without the renderer). Its per-pixel error is
eval/metrics.py rel_mse_map (tests/eval/test_metrics.py)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl.eval.scenes.motion_validation import garden_orbit, motion_scene

from tools.experiments import taa_floor as tool


@pytest.fixture(scope="module")
def orbit():
    return motion_scene("garden_orbit", 24, 16, 6)


def flat(value: float) -> np.ndarray:
    return np.full((16, 24, 3), value, np.float32)


def test_converged_input_of_flat_frames_is_that_colour(orbit):
    # every frame's sample replaced by 0.25: the history, the clip box and the blend all hold 0.25, whatever the
    # scene renders
    refs = {f: flat(0.25) for f in range(orbit.frames)}
    got = tool.taa_run(orbit, "ris", 1, "converged_input", refs, [2, 5])
    assert sorted(got) == [2, 5]
    for img, n, _ in got.values():
        np.testing.assert_allclose(img, 0.25, rtol=1e-6)
        assert n.max() >= 2.0  # the history was kept somewhere: the blend above was not just the sample


def test_converged_both_blends_the_oracle_history_with_the_frame():
    # a still camera: TAA neither reprojects nor clips, it averages, f = s / n + (1 - 1 / n) h with n the history
    # length it writes; frame 4's sample replaced by 1 and its history by 0 give 1 / n in every pixel
    still = garden_orbit(24, 16, 6, step_deg=0.0)
    refs = {3: flat(0.0), 4: flat(1.0)}
    img, n, _ = tool.taa_run(still, "ris", 1, "converged_both", refs, [4])[4]
    assert n.min() == 5.0 and n.max() == 5.0  # frames 0-4 of an unbroken history
    np.testing.assert_allclose(img, 0.2, rtol=1e-6)

