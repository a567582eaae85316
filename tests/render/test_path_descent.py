"""NEE at path vertices picks its light from the tree by the stratified descent of its Sobol word where the still
draws from the Sobol sequence (opencl/path/nee.h, lights/tree.h light_tree_descend): the still's mean with bounces
equals that of the exhaustive `reference` method (whose path pass descends with random numbers, checked against
the independent numpy path tracer in test_paths.py) within the standard errors of both, on a box lit by a panel and
six point lights of equal power, bright beside the panel so that light picked at path vertices is most of the
bounced light, at their own distances from each vertex, so that the tree has three levels and its branches unequal
probabilities (the light tree's k-d leaves and near/far importance leave a descent without its remap only 0.3 % off
with lights of powers over two decades, too little to be seen). Its 7 lights are fewer than LIGHT_TREE_EXACT, so the
descent picks one of them by its own importance from the root (lights/tree_exact.h), taking the uniform as it is;
the check is also run with the kernels built to branch down to every leaf (TEST_LIGHT_TREE_EXACT=1), where the
branches remap it. Built so, the same check rejects a descent that forgets to remap its uniform
(TEST_DESCENT_WITHOUT_REMAP), which shows it sees a wrong pick probability at the lower levels."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Light, Renderer, Settings, translation

from ..bias_controls import built_with
from ..stats import disagreement
from .path_reference import path_test_scene

BATCHES, FRAMES, REFERENCE_FRAMES = 8, 64, 256
BOUNCES = 2


def _scene():
    scene = path_test_scene(light="quad")
    places = [(-1.1, -1.0, 0.4), (1.1, 1.0, 0.5), (-1.0, 1.1, 2.0), (1.2, -1.1, 1.8), (0.0, 1.2, 0.3),
              (-0.2, -1.2, 2.2)]
    for k, pos in enumerate(places):
        scene.lights.append(Light(f"point{k}", "point", (1.0, 0.9, 0.8), 300.0, translation(*pos), radius=0.05))
    return scene


def _mean(scene, settings: Settings, frames: int) -> tuple[np.ndarray, np.ndarray]:
    """Mean image and its standard error over BATCHES still renders with their own seeds."""
    means = [Renderer(scene, Settings(**{**settings.__dict__, "seed": 301 + b, "jitter": False}))
             .render_still(0, samples=frames).color[..., :3].astype(np.float64) for b in range(BATCHES)]
    m = np.stack(means)
    return m.mean(axis=0), m.std(axis=0, ddof=1) / math.sqrt(BATCHES)


def _problems() -> list[str]:
    scene = _scene()
    paths = dict(max_bounces=BOUNCES, diffuse_bounces=BOUNCES, glossy_bounces=BOUNCES)
    r = Renderer(scene, Settings(method="ris", **paths))
    assert r.path_light_tree and r.flags["HAS_LIGHT_TREE"] and len(r.device_scene.lights) == 7
    ours, ours_se = _mean(scene, Settings(method="ris", sampler="sobol", **paths), FRAMES)
    ref, ref_se = _mean(scene, Settings(method="reference", **paths), REFERENCE_FRAMES)
    return disagreement(ours, np.sqrt(ours_se**2 + ref_se**2), ref, batches=BATCHES, exact_rtol=1e-5)


@pytest.mark.parametrize("branches", [False, True])
def test_stratified_path_descent_mean_equals_the_reference(device, monkeypatch, branches):
    if branches:
        built_with(monkeypatch, "TEST_LIGHT_TREE_EXACT=1")
    problems = _problems()
    assert not problems, problems


def test_the_check_rejects_a_descent_without_its_remap(device, monkeypatch):
    built_with(monkeypatch, "TEST_LIGHT_TREE_EXACT=1", "TEST_DESCENT_WITHOUT_REMAP=1")
    problems = _problems()
    assert any("image means" in p or "values beyond" in p for p in problems), problems
