"""The per-pixel light pick of still RIS renders (lights/pick_table.py, light_proposal "auto"/"pixel"): its rows are
probability distributions that give every emitting light at least FLOOR of its light-array pdf, it is used only
where it applies, and RIS over its candidates is unbiased (mean equal to the exhaustive reference within 4
standard errors, per pixel and over the image) on the scene with every light type, powers 1e-6..1e6, a light
touching the floor, a grazing sun and lights behind the surface; with BSDF candidates and with the BSDF MIS
sample too, whose MIS weights take the table's pdf of the light a BSDF ray met (light_pick_pdf)."""

import numpy as np
import pytest
from restircl import Light, Renderer, translation
from restircl.lights.pick_table import FLOOR, MAX_LIGHTS, ONE, uses_table

from .. import helpers as h
from ..bias_controls import wrong_pdf
from ..render.test_estimators import SIZES

W, H = 16, 12


def collect_with_table(scene, settings, frames, device):
    """(frames, H, W, 3) per-frame estimates of a still camera, picking from one per-pixel table made from the
    first frame's G-buffer (as a still render does); the Renderer, for its table."""
    r = Renderer(scene, settings, device)
    assert r.flags["HAS_PICK_TABLE"]
    r.pick_table.start(True)
    out = np.stack([r.render_frame(0, still=True).noisy for _ in range(frames)]).astype(np.float64)
    assert r.pick_table.ready
    return out, r


@pytest.fixture(scope="module")
def reference(reference_samples):
    return reference_samples(h.mixed_lights_scene(W, H), h.Settings(method="reference", seed=101, jitter=False),
                             SIZES["quick"][0])


def test_rows_are_distributions_with_the_floor(device):
    scene = h.mixed_lights_scene(W, H)
    _, r = collect_with_table(scene, h.Settings(method="ris", jitter=False, sampler="random"), 1, device)
    n = len(r.lights.power)
    assert 2 <= n <= MAX_LIGHTS
    p = r.pick_table.read(n)
    assert p.shape == (W * H, n)
    assert np.all(p >= 0) and np.allclose(p.sum(axis=1), 1.0, atol=0)
    emits = r.light_array.pdf > 0
    # every emitting light keeps FLOOR of its array pdf (less the rounding to 1 / 65536 and one count)
    assert np.all(p[:, emits] >= FLOOR * r.light_array.pdf[emits] - 2.0 / ONE)
    # the pixels differ: the table is not the array's pdf everywhere (the estimate moved the probabilities)
    assert np.abs(p - r.light_array.pdf).max() > 0.1


def test_applies_to_still_ris_of_few_lights_only():
    assert uses_table("auto", "ris", 7, still=True) and uses_table("pixel", "ris", 16, still=True)
    assert not uses_table("array", "ris", 7, still=True)
    assert not uses_table("auto", "ris", 7, still=False)
    assert not uses_table("auto", "restir", 7, still=True)
    assert uses_table("auto", "ris", 64, still=True) and not uses_table("auto", "ris", 65, still=True)
    assert not uses_table("auto", "ris", MAX_LIGHTS + 1, still=True)
    assert not uses_table("auto", "ris", 1, still=True)


def test_animation_frames_do_not_use_the_table(device):
    """A still render leaves the table off for the frames after it: they are the light array's, bit for bit."""
    scene = h.mixed_lights_scene(W, H)
    s = h.Settings(method="ris", jitter=False, sampler="random", seed=3)
    a = Renderer(scene, s, device)
    a.render_still(0, 2)
    assert not a.pick_table.active
    b = Renderer(scene, h.Settings(method="ris", jitter=False, sampler="random", seed=3, light_proposal="array"),
                 device)
    b.render_still(0, 2)
    assert np.array_equal(a.render_frame(0, still=True).noisy, b.render_frame(0, still=True).noisy)


@pytest.mark.parametrize("extra", [{}, {"bsdf_sampling": "on"}, {"bsdf_mis_sample": True}],
                         ids=["light_only", "bsdf_candidates", "bsdf_mis_sample"])
def test_ris_with_the_table_matches_reference(device, reference, extra):
    frames, batches = SIZES["quick"]
    s = h.Settings(method="ris", candidates=2, seed=9, jitter=False, sampler="random", **extra)
    samples, _ = collect_with_table(h.mixed_lights_scene(W, H), s, frames, device)
    assert np.all(np.isfinite(samples))
    h.assert_mean_equals_reference(samples, reference, batches, f"table {extra}")


def many_lights_scene():
    """mixed_lights with 36 more small point lights over the floor (49 light records: above the old cap of 16)."""
    scene = h.mixed_lights_scene(W, H)
    rng = np.random.default_rng(4)
    for k in range(36):
        x, y = rng.uniform(-1.8, 1.8, 2)
        scene.lights.append(Light(f"extra{k}", "point", tuple(rng.uniform(0.3, 1.0, 3)), float(10 ** rng.uniform(0, 2)),
                                  translation(float(x), float(y), float(rng.uniform(0.1, 1.5))), radius=0.02 * (k % 2)))
    return scene.validate()


def test_ris_with_a_table_of_many_lights_matches_reference(device, reference_samples):
    """A row of 49 lights (the bisection of pick_table_light over a long row; the table kernel's arrays) is a
    distribution with the floor, and RIS over its candidates is unbiased."""
    frames, batches = SIZES["quick"]
    scene = many_lights_scene()
    ref = reference_samples(scene, h.Settings(method="reference", seed=101, jitter=False), frames)
    s = h.Settings(method="ris", candidates=2, seed=9, jitter=False, sampler="random")
    samples, r = collect_with_table(scene, s, frames, device)
    n = len(r.lights.power)
    assert 16 < n <= MAX_LIGHTS
    p = r.pick_table.read(n)
    emits = r.light_array.pdf > 0
    assert np.allclose(p.sum(axis=1), 1.0, atol=0)
    assert np.all(p[:, emits] >= FLOOR * r.light_array.pdf[emits] - 2.0 / ONE)
    h.assert_mean_equals_reference(samples, ref, batches, "table of 49 lights")


def test_the_harness_rejects_a_wrong_pdf(device, reference, monkeypatch):
    """Negative control: the table's candidates with a pdf 2 % too small (tests/bias_controls.py) are rejected."""
    frames, batches = SIZES["quick"]
    wrong_pdf(monkeypatch)
    s = h.Settings(method="ris", candidates=2, seed=9, jitter=False, sampler="random")
    samples, _ = collect_with_table(h.mixed_lights_scene(W, H), s, frames, device)
    with pytest.raises(AssertionError, match="outliers|image means"):
        h.assert_mean_equals_reference(samples, reference, batches, "table, wrong pdf")
