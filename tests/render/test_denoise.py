"""Denoising with Intel Open Image Denoise (Settings.denoise, restircl/render/denoise.py)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Material, Renderer, Settings, scenes
from restircl.io.images import exr_channels
from restircl.render import denoise as dn

from ..helpers import rel_mse

pytestmark = pytest.mark.skipif(not dn.available(), reason="pyoidn is not installed (pip install pyoidn)")


def _cornell(width: int = 96, height: int = 72):
    return scenes.cornell_box(width, height)


@pytest.fixture(scope="module")
def reference() -> np.ndarray:
    """The cornell box converged: the exhaustive estimator (one light) over 256 jittered frames."""
    r = Renderer(_cornell(), Settings(method="reference", seed=7))
    return r.render_still(0, 256).color[..., :3]


def test_denoised_still_is_closer_to_the_reference_than_the_noisy_one(reference):
    """At 4 samples of RIS the image is noisy; OIDN guided by the accumulated albedo and normal brings it closer
    to the converged image, and keeps the noisy one as the Noisy Image pass. Three seeds, each must improve."""
    for seed in (1, 2, 3):
        f = Renderer(_cornell(), Settings(method="ris", seed=seed, denoise=True)).render_still(0, 4)
        assert f.noisy_image is not None and np.all(np.isfinite(f.color))
        noisy, clean = rel_mse(f.noisy_image[..., :3], reference), rel_mse(f.color[..., :3], reference)
        assert clean < 0.5 * noisy, (seed, clean, noisy)
        assert np.array_equal(f.color[..., 3], f.noisy_image[..., 3])


def test_lamps_seen_directly_are_not_smeared():
    """many_lights shows small bright lamps: the emission the camera sees is left out of the denoiser and added
    back, so the denoised image is closer to the reference by relMSE too (smeared over the dark ground, the lamps
    made it 18x worse)."""
    sc = scenes.many_lights(64, 36, frames=1)
    ref = Renderer(sc, Settings(method="ris", candidates=16, seed=9)).render_still(0, 256).color
    f = Renderer(sc, Settings(method="ris", seed=4, denoise=True)).render_still(0, 4)
    assert rel_mse(f.color, ref) < rel_mse(f.noisy_image, ref)


def test_the_noisy_image_is_what_the_renderer_gives_without_the_denoiser():
    sc = _cornell(32, 24)
    plain = Renderer(sc, Settings(method="ris", seed=5)).render_still(0, 3)
    den = Renderer(sc, Settings(method="ris", seed=5, denoise=True)).render_still(0, 3)
    assert plain.noisy_image is None
    np.testing.assert_array_equal(den.noisy_image, plain.color)
    assert not np.array_equal(den.color, plain.color)
    ch = exr_channels(den)
    assert {"NoisyImage.R", "NoisyImage.A"} <= set(ch) and "NoisyImage.R" not in exr_channels(plain)


def test_guides_are_the_mean_of_the_samples_and_a_metal_is_not_black():
    """Without jitter every sample sees the same surface: the accumulated albedo is the G-buffer's, exactly,
    on the diffuse walls; a metal (diffuse albedo 0) gets its F0 as the guide, times the lobe's weight, which
    carries the multiscatter GGX energy compensation for the view: at least 1, and at roughness 0.3 at most
    1 / 0.88 (the least single-scatter albedo over views, ggx_tables.directional_albedo), below 1.2."""
    sc = _cornell(32, 24)
    s = dict(method="ris", seed=3, jitter=False)
    plain = Renderer(sc, Settings(**s)).render_still(0, 2)
    den = Renderer(sc, Settings(**s, denoise=True)).render_still(0, 2)
    np.testing.assert_allclose(den.albedo, plain.albedo, atol=1e-6)
    np.testing.assert_allclose(den.normal, plain.normal, atol=1e-5)
    gold = (1.0, 0.78, 0.34)
    sc.materials[0] = Material("white", gold, metallic=1.0, roughness=0.3, kind="principled")
    metal = Renderer(sc, Settings(**s, denoise=True)).render_still(0, 2)
    diffuse_albedo = Renderer(sc, Settings(**s)).render_still(0, 2).albedo
    walls = np.all(diffuse_albedo < 1e-6, axis=-1) & np.any(metal.normal != 0, axis=-1)  # the metal surfaces
    assert walls.sum() > 50
    guide, f0 = metal.albedo[walls], np.broadcast_to(np.float32(gold), (walls.sum(), 3))
    assert np.all(guide >= f0 - 1e-5) and np.all(guide <= np.minimum(1.2 * f0, 1.0) + 1e-5)


def test_animation_frames_are_denoised_with_their_own_g_buffer():
    sc = scenes.many_lights(48, 27, frames=3)
    r = Renderer(sc, Settings(denoise=True))
    for k in range(3):
        f = r.render_frame(k, aovs=k != 1)  # without the AOV read-back too
        assert f.noisy_image is not None and np.all(np.isfinite(f.color))


def test_bad_input_never_reaches_the_image():
    rng = np.random.default_rng(0)
    img = rng.random((16, 16, 3)).astype(np.float32)
    img[3, 4] = np.nan
    img[5, 6] = np.inf
    img[7, 8] = -3.0
    out = dn.denoise_image(img, np.full_like(img, np.nan), rng.normal(size=img.shape).astype(np.float32) * 5)
    assert out.shape == (16, 16, 3) and np.all(np.isfinite(out)) and np.all(out >= 0)


def test_without_pyoidn_the_image_is_kept_with_one_warning(monkeypatch):
    monkeypatch.setattr(dn, "available", lambda: False)
    r = Renderer(_cornell(16, 12), Settings(method="ris", denoise=True))
    with pytest.warns(UserWarning, match="pyoidn"):
        f = r.render_still(0, 2)
    assert f.noisy_image is None and np.all(np.isfinite(f.color))
