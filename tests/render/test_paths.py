"""The path pass (Settings.max_bounces, opencl/path/) is unbiased: its mean, with the direct light of two direct
estimators, equals the independent numpy path tracer's (tests/render/path_reference.py: pure BSDF sampling, no NEE,
no MIS, sharing no code with the kernels) within the standard errors of both, per pixel and over the image, at 1, 3
and 8 bounces, on a box lit by an area light and an emissive mesh with and without a world. The same harness rejects a
deliberately biased kernel (Russian roulette without its 1/q), which shows it has the power to see such a bias.
Max Bounces 0 compiles no path code and renders the images of the direct light alone."""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest
from restircl import Renderer, Settings

from ..bias_controls import built_with
from ..stats import disagreement
from .path_reference import PathEstimate, path_test_scene, trace_paths

BATCHES, FRAMES = 8, 96  # our side: independent seeds, each a still of FRAMES frames
# The numpy reference costs most of this file and its noise rules the bounds (its standard errors 1.2-5 times ours).
# With 8192 paths the negative control is still rejected: image means 11.0, 9.3 and 4.5 standard errors off (R, G, B;
# 14.5, 12.7, 6.0 with 16384); the smallest bias the image check rejects is then about 2.0 / 2.1 / 2.7 % (1.5 / 1.6 /
# 2.0 % with 16384; docs/measurements/benchmarks.md, "Test suite time")
REFERENCE_PATHS = 8192
# the deepest bounce count any test here asks of each light's scene: its one reference trace goes that deep
REFERENCE_BOUNCES = {"both": 8, "quad": 3}


def _ours(scene, settings: Settings) -> tuple[np.ndarray, np.ndarray]:
    """Mean image and its standard error over BATCHES independent still renders."""
    means = []
    for b in range(BATCHES):
        r = Renderer(scene, Settings(**{**settings.__dict__, "seed": 101 + b, "jitter": False}))
        means.append(r.render_still(0, samples=FRAMES).color[..., :3].astype(np.float64))
    m = np.stack(means)
    return m.mean(axis=0), m.std(axis=0, ddof=1) / math.sqrt(BATCHES)


@functools.cache
def _reference(light: str, world: tuple[float, float, float] | None) -> PathEstimate:
    """One numpy trace per scene, shared by the tests of this file (the check and its negative control see the same
    reference): without roulette the first b + 1 rays of a deeper path are distributed as a path of b bounces, so
    cumulative[b] of the deeper trace estimates Max Bounces b as a trace of b bounces would."""
    return trace_paths(path_test_scene(light=light, world=world), REFERENCE_BOUNCES[light], REFERENCE_PATHS, seed=7)


def _against_reference(light: str, world: tuple[float, float, float] | None, bounces: int,
                       method: str) -> list[str]:
    scene = path_test_scene(light=light, world=world)
    ours, ours_se = _ours(scene, Settings(method=method, max_bounces=bounces, diffuse_bounces=bounces,
                                          glossy_bounces=bounces))
    ref = _reference(light, world)
    expected, ref_se = ref.cumulative[bounces], ref.cumulative_se[bounces]
    # values without noise (an emitter the camera sees) agree to float32 rounding
    return disagreement(ours, np.sqrt(ours_se**2 + ref_se**2), expected, batches=BATCHES, exact_rtol=1e-5)


@pytest.mark.parametrize(("light", "world", "bounces", "method"), [
    ("both", None, 1, "ris"),
    ("both", None, 8, "ris"),
    ("quad", (0.2, 0.25, 0.3), 3, "restir"),
])
def test_path_mean_equals_the_reference(device, light, world, bounces, method):
    problems = _against_reference(light, world, bounces, method)
    assert not problems, problems


def test_the_harness_rejects_roulette_without_its_divide(device, monkeypatch):
    """Negative control: the kernel built with PATH_ROULETTE_WITHOUT_DIVIDE drops Russian roulette's 1/q, so the
    light of the bounces after the second comes out too dark (about 5 % of the image at 8 bounces); the check above
    must fail on it."""
    built_with(monkeypatch, "PATH_ROULETTE_WITHOUT_DIVIDE=1")
    problems = _against_reference("both", None, 8, "ris")
    assert any("image means" in p for p in problems), problems


def test_max_bounces_zero_has_no_path_pass(device):
    scene = path_test_scene()
    r = Renderer(scene, Settings(method="ris", jitter=False))
    assert "paths" not in r.features and "path_trace" not in r.kernels.k
    # animation frames: the path pass where ReSTIR GI is off (tests/render/test_restir_gi.py has it on)
    with_paths = Renderer(scene, Settings(method="ris", jitter=False, max_bounces=2, gi_reuse=False))
    assert "paths" in with_paths.features and "path_trace" in with_paths.kernels.k
    a = r.render_frame(0)
    b = Renderer(scene, Settings(method="ris", jitter=False, max_bounces=0, diffuse_bounces=9)).render_frame(0)
    assert np.array_equal(a.color, b.color)
    assert "paths" not in b.stage_ms and "paths" in with_paths.render_frame(0).stage_ms
