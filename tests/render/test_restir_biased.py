"""ReSTIR DI's biased merge (bias_correction "none", restir/reuse.h): where nothing occludes, its estimate is
unbiased. The merge weighs its inputs by their M; normalised by the M of every input it would count an input that
cannot produce the chosen sample (its target there is 0) and darken the pixel by that input's share of M, which is
largest for a pixel without history that merges the disocclusion boost's neighbours, or a permuted neighbour's
history. It counts the M of the inputs whose target holds the sample (1/Z without the shadow rays), so that its bias
is the visibility's alone (tests/render/test_restir.py measures that one on the occluder scene).

The scene: a spot light's disc on a floor, beside a point light. A neighbour outside the disc cannot hold the spot's
sample; with the plain 1/M the disc came out 22-61 % dark (the negative control)."""

import numpy as np
import pytest
from restircl import Light, Scene, Settings, look_at, scenes, translation
from restircl.materials.material import Material
from restircl.scene.camera import Camera
from restircl.scene.mesh import Mesh

from ..bias_controls import built_with
from ..helpers import batch_stats, luminance, run_means
from .test_restir import SIZES, assert_matches

W, H = 16, 12
RUNS, FRAMES, REF_FRAMES = SIZES["quick"]


def spot_edge_scene() -> Scene:
    """A floor lit by a spot light whose hard-edged disc fills a fifth of the image, and a point light."""
    fv, ft = scenes.quad(6, 6)
    lights = [
        Light(
            "spot", "spot", (1, 1, 1), 200.0, look_at((0.0, 0.0, 2.0), (0.3, 0.2, 0.0)), spot_size=0.9, spot_blend=0.0
        ),
        Light("fill", "point", (1, 1, 1), 20.0, translation(-1.5, 1.0, 2.5), radius=0.1),
    ]
    cam = Camera(look_at((0.0, -4.0, 3.0), (0.0, 0.0, 0.3)), W, H, lens=30.0)
    return Scene([Mesh("floor", fv, ft, 0)], [Material("grey", (0.7, 0.7, 0.7))], lights, cam, name="spot_edge")


@pytest.fixture(scope="module")
def reference(reference_samples):
    return batch_stats(
        luminance(
            reference_samples(spot_edge_scene(), Settings(method="reference", seed=55, jitter=False), REF_FRAMES)
        ),
        32,
    )


# default: temporal reuse from a permuted neighbour, then spatial; no_temporal: every pixel is without history and
# merges the disocclusion boost's 8 neighbours
CONFIGS = {"default": dict(), "no_temporal": dict(temporal=False)}


def biased_runs(config: str, device) -> np.ndarray:
    s = Settings(method="restir", bias_correction="none", jitter=False, taa=False, seed=5, **CONFIGS[config])
    runs = run_means(spot_edge_scene(), s, RUNS, FRAMES, device)
    assert np.all(np.isfinite(runs))
    return runs


@pytest.mark.parametrize("config", list(CONFIGS))
def test_biased_merge_is_unbiased_where_nothing_occludes(device, reference, config):
    assert_matches(biased_runs(config, device), reference, f"spot edge biased merge, {config}")


def test_the_harness_rejects_the_plain_m_normalisation(device, reference, monkeypatch):
    """Negative control: the merge normalised by every input's M (TEST_BIASED_PLAIN_M, tests/bias_controls.py)."""
    built_with(monkeypatch, "TEST_BIASED_PLAIN_M")
    runs = biased_runs("default", device)
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_matches(runs, reference, "spot edge, plain 1/M")
