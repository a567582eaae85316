"""Every path that the still estimator (render/still_method.py) chooses for an F12 render is unbiased, as chosen:
the settings still_settings gives each kind of scene (a world alone: one candidate from the world's cumulative table
under Sobol beside the BSDF MIS sample; one light object: one candidate under Sobol; a few light objects: the
per-pixel pick table; emissive meshes: BSDF candidates) render, through Renderer.render_still, the mean of the
exhaustive `reference` method (every light, each sampled by its own light_sample: no pick, no table, no RIS, no
MIS, no Sobol; the world by one sample of its importance table, whose density the reference divides by: a
different estimator of the same integral) within the standard errors of both (tests/stats.disagreement).

Each case is paired with its negative control (tests/bias_controls.py): the chosen path built with a deliberately
biased kernel must be rejected by the same check. The paths' decisions themselves are asserted first, so that a
change of rule that moves a scene to another path shows here rather than leaving a path untested."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Environment, Renderer, Settings, still_settings
from restircl.lights.pick_table import uses_table
from restircl.scenes.hdri_sky import sky_map

from ..bias_controls import built_with, wrong_pdf
from ..stats import disagreement
from .test_still_method import _scene

BATCHES, SAMPLES = 8, 32  # independent still renders (own seeds) of SAMPLES samples each
REFERENCE_SAMPLES = 256


def _world_alone():
    scene = _scene()
    scene.environment = Environment("sunny", color=(1, 1, 1), image=sky_map(64, 128))
    return scene


# kind: (scene, the settings still_settings must choose (those different from the defaults), the negative control)
CASES = {
    "world_alone": (_world_alone, dict(method="ris", candidates=1, bsdf_mis_sample=True), "TEST_WITHOUT_MIS_WEIGHT"),
    "one_light": (lambda: _scene(("area",)), dict(method="ris", candidates=1), None),
    "few_lights": (lambda: _scene(("point", "spot", "sun", "area")), dict(method="ris", candidates=2), None),
    "emissive_mesh": (lambda: _scene(("point",), emissive=True), dict(method="ris", bsdf_sampling="on"),
                      "TEST_WITHOUT_MIXTURE_PDF"),
}


def _batches(scene, settings: Settings, samples: int) -> tuple[np.ndarray, np.ndarray]:
    means = []
    for b in range(BATCHES):
        r = Renderer(scene, Settings(**{**settings.__dict__, "seed": 301 + b}))
        means.append(r.render_still(0, samples=samples).color[..., :3].astype(np.float64))
    m = np.stack(means)
    return m.mean(axis=0), m.std(axis=0, ddof=1) / math.sqrt(BATCHES)


@pytest.fixture(scope="module")
def references(device):
    out = {}

    def get(kind: str):
        if kind not in out:
            out[kind] = _batches(CASES[kind][0](), Settings(method="reference", jitter=False), REFERENCE_SAMPLES)
        return out[kind]

    return get


def _problems(kind: str, reference) -> list[str]:
    scene = CASES[kind][0]()
    chosen = still_settings(Settings(jitter=False), scene)
    mean, se = _batches(scene, chosen, SAMPLES)
    expected, ref_se = reference
    sigma = np.sqrt(se**2 + ref_se**2)
    level = expected.reshape(-1, 3).mean(axis=0)
    pooled = np.sqrt((sigma.reshape(-1, 3) ** 2).sum(axis=0)) / (sigma.size // 3)
    print(f"{kind}: image mean {(mean.reshape(-1, 3).mean(axis=0) / level - 1).round(4)}, rejects |bias| > "
          f"{(4 * pooled / level).round(4)}")
    return disagreement(mean, sigma, expected, batches=BATCHES, exact_rtol=1e-5)


@pytest.mark.parametrize("kind", list(CASES))
def test_the_chosen_path_is_unbiased(device, references, kind):
    scene = CASES[kind][0]()
    chosen = still_settings(Settings(), scene)
    for name, value in CASES[kind][1].items():
        assert getattr(chosen, name) == value, (kind, name)
    if kind == "few_lights":
        assert uses_table(chosen.light_proposal, chosen.method, len(scene.lights), still=True)
    problems = _problems(kind, references(kind))
    assert not problems, problems


@pytest.mark.parametrize("kind", list(CASES))
def test_the_harness_rejects_the_biased_path(device, references, kind, monkeypatch):
    """Negative control: the dropped MIS weight against the BSDF sample (world alone), light candidates without the
    mixture density beside BSDF candidates (emissive mesh), a light pdf 2 % too small (the rest)."""
    reference = references(kind)
    control = CASES[kind][2]
    if control is None:
        wrong_pdf(monkeypatch)
    else:
        built_with(monkeypatch, control)
    problems = _problems(kind, reference)
    assert any("image means" in p or "values beyond" in p for p in problems), problems
