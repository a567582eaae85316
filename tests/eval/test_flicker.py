"""The flicker metric (restircl/eval/report/flicker.py, `restircl report --flicker`)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import scenes
from restircl.cli.main import main
from restircl.eval.report import flicker as fl


def _ref(h: int = 24, w: int = 32) -> np.ndarray:
    yy, xx = np.mgrid[0:h, 0:w]
    return np.repeat((0.3 + 0.2 * np.sin(xx / 5.0) * np.cos(yy / 7.0))[..., None], 3, axis=2)


def test_white_noise_is_all_flicker_and_an_offset_is_none():
    """Independent noise per frame: the temporal std is the error (ratio ~ 1, below by the std's own small-sample
    bias: for 64 frames E[std] / sigma is about 0.99); a steady offset: flicker 0, ratio 0."""
    rng = np.random.default_rng(1)
    ref = _ref()
    noisy = [ref + rng.normal(0, 0.05, ref.shape) for _ in range(64)]
    s = fl.stats("n", "still", noisy, [ref] * 64)
    assert 0.95 < s.ratio < 1.0 and s.boiling == 0
    steady = [ref + 0.05] * 64
    t = fl.stats("o", "still", steady, [ref] * 64)
    assert t.flicker < 1e-12 and t.error > 0.03 and t.ratio < 1e-9


def test_level_is_the_mean_luminance_over_the_references():
    """level: 1 for the reference itself, 0.8 for an image 20 % too dark."""
    ref = _ref()
    assert fl.stats("r", "still", [ref] * 4, [ref] * 4).level == pytest.approx(1.0)
    assert fl.stats("d", "still", [ref * 0.8] * 4, [ref] * 4).level == pytest.approx(0.8)


def test_a_blotch_boils_and_a_highlight_of_the_reference_does_not():
    ref = _ref()
    ref[5, 5] = 50.0  # a small light seen directly: in the reference too
    x = ref.copy()
    x[12, 20] = 10.0  # one lucky sample copied into a pixel
    mask = fl.boiling_mask(x, ref)
    assert mask[12, 20] and mask.sum() == 1
    assert fl.boiling_mask(ref, ref).sum() == 0


def test_slowed_camera_keeps_the_path_and_its_ends():
    sc = scenes.many_lights(16, 9, frames=4)
    slow = fl.slowed(sc, 8)
    assert slow.frames == 25 and slow.camera.transforms.shape == (25, 4, 4)
    np.testing.assert_allclose(slow.camera.transforms[::8], sc.camera.transforms, atol=1e-12)
    r = slow.camera.transforms[3, :3, :3]
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-9)


def test_report_flicker_on_a_small_scene(tmp_path, capsys):
    rc = main(["report", "cornell_box", "--width", "24", "--height", "16", "--flicker", "--flicker-frames", "6",
               "--methods", "ris,restir", "--reference-seconds", "1", "--cache-dir", str(tmp_path / "refs"),
               "--out", str(tmp_path)])
    assert rc == 0
    text = capsys.readouterr().out
    assert "| ris | still |" in text and "| restir | still |" in text
    assert (tmp_path / "flicker_cornell_box_still.json").exists()
