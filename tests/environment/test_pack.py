"""The environment's texels as the device stores them (environment/pack.py): half floats divided by a power of two
(never Inf, however bright), float32 where the range needs it, bad texels zeroed without touching the source, the
tables built band by band equal to one build of the whole map, and half against float32 on the device."""

import math
import warnings

import numpy as np
import pytest
from restircl import Environment, Renderer, Settings
from restircl.environment.pack import HALF_NORMAL_MIN, HALF_TOP, choose_format, map_stats, store_texels, texel_floats
from restircl.environment.table import TABLE_KINDS, build_table, texel_weights
from restircl.lights import environment
from restircl.lights.record import LUMINANCE
from restircl.scenes.hdri_sky import sky, sky_map


def stored(rgb: np.ndarray, fmt: str):
    stats = map_stats(rgb)
    out = np.empty(texel_floats(*rgb.shape[:2], fmt), np.float32)
    return store_texels(rgb, stats, fmt, out)


@pytest.mark.parametrize("top", [1e-3, 1.0, 2e3, 1e5, 3e9])
def test_half_texels_round_within_half_precision_and_stay_finite(top):
    """Whatever the brightest texel (above half's 65504 too), the stored texels decode to the source within 2^-11
    of each texel (its rounding), and the brightest is stored at most at 2^15."""
    rgb = sky_map(16, 32).astype(np.float64)
    rgb *= top / rgb.max()
    rgb = rgb.astype(np.float32)
    s = stored(rgb, "half")
    raw = s.rows(0, 16)
    assert np.all(np.isfinite(raw)) and raw.max() <= HALF_TOP
    assert math.log2(s.scale) == int(math.log2(s.scale))  # a power of two: exact in the record's radiance
    np.testing.assert_allclose(s.texels(), rgb, rtol=2.0 ** -11, atol=0)


def test_float_texels_are_the_source():
    rgb = sky_map(8, 16)
    np.testing.assert_array_equal(stored(rgb, "float").texels(), rgb)


def test_auto_keeps_float32_where_half_would_lose_the_dim_texels():
    rgb = np.ones((4, 8, 3), np.float32)
    assert choose_format(map_stats(rgb), "auto") == "half"
    rgb[0, 0] = 2.0 ** 29  # 2^29 above the dimmest: still every texel a normal half after the scale
    assert choose_format(map_stats(rgb), "auto") == "half"
    rgb[0, 0] = 2.0 ** 31
    assert choose_format(map_stats(rgb), "auto") == "float"
    assert map_stats(rgb).bottom / 2.0 ** (31 - 15) < HALF_NORMAL_MIN
    assert choose_format(map_stats(np.zeros((2, 2, 3), np.float32)), "auto") == "half"
    with pytest.raises(ValueError, match="texel format"):
        choose_format(map_stats(rgb), "fp8")


def test_bad_texels_are_zeroed_in_the_store_not_in_the_source():
    rgb = sky_map(8, 16)
    rgb[1, 2] = np.nan
    rgb[2, 3, 1] = np.inf
    rgb[3, 4, 2] = -5.0
    before = rgb.copy()
    for fmt in ("half", "float"):
        s = stored(rgb, fmt)
        tex = s.texels()
        assert s.zeroed == 3 and np.all(np.isfinite(tex)) and tex.min() >= 0
        assert np.all(tex[1, 2] == 0) and np.all(tex[2, 3] == 0) and np.all(tex[3, 4] == 0)
    np.testing.assert_array_equal(rgb, before)


def test_packed_map_warns_once_naming_the_world():
    img = sky_map(8, 16)
    img[0, 0] = np.nan
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        packed = environment.packed_map(Environment("dirty", color=(1, 1, 1), image=img))
    msgs = [str(w.message) for w in caught]
    assert packed.zeroed == 1 and len(msgs) == 1 and "'dirty'" in msgs[0]


@pytest.mark.parametrize("kind", TABLE_KINDS)
def test_tables_built_in_bands_equal_one_build(kind, monkeypatch):
    """Bands of 3 rows (the build of a huge map) give the table one band of every row gives, bit for bit."""
    from restircl.environment import table as environment_table

    rng = np.random.default_rng(5)
    lum = rng.uniform(0, 1, (20, 12)) ** 3
    lum[7] = 0.0
    whole = build_table(lum, kind)
    monkeypatch.setattr(environment_table, "CHUNK_TEXELS", 3 * 12)
    monkeypatch.setattr(environment_table, "ALIAS_BAND_TEXELS", 3 * 12)
    np.testing.assert_array_equal(build_table(lum, kind), whole)
    out = np.empty_like(whole)
    total = environment_table.fill_table(lum, kind, out)
    assert total == pytest.approx(texel_weights(lum).sum(), rel=1e-12)


def test_tables_sample_the_stored_luminance():
    """The alias pdf is luminance(stored texel) x norm on the device: the table is built from the same values."""
    img = sky_map(16, 32)
    packed = environment.packed_map(Environment(color=(1, 1, 1), image=img), kind="alias", texel_format="half")
    lum = packed.stored.rows(0, 16).astype(np.float64) @ LUMINANCE
    np.testing.assert_array_equal(packed.table, build_table(lum, "alias"))
    assert packed.weight_sum == pytest.approx(texel_weights(lum).sum(), rel=1e-12)


def frame_means(fmt: str, img: np.ndarray, frames: int = 24) -> np.ndarray:
    old = environment.TEXEL_FORMAT
    environment.TEXEL_FORMAT = fmt
    try:
        scene = sky(32, 20, map_height=32)
        scene.environment = Environment("bright", color=(1, 1, 1), image=img)
        r = Renderer(scene, Settings(method="ris", seed=4, taa=False))
        assert r.device_scene.lights.environment.stored.fmt == fmt
        return np.array([r.render_frame(0, still=True).color[..., :3].mean() for _ in range(frames)])
    finally:
        environment.TEXEL_FORMAT = old


@pytest.mark.parametrize("sun", [1e5, 1e7])
def test_half_and_float_texels_render_the_same_sun(sun):
    """The sun-1e5 stress case, and a sun of 1e7 times the sky (far above half's 65504): half and float32 maps
    render finite images whose means agree within 4 standard errors of the frames' spread."""
    img = sky_map(32, 64, sun_scale=1.0)
    img[img.max(axis=2) > 100] = sun * img[0, 0]
    half, full = frame_means("half", img), frame_means("float", img)
    assert np.all(np.isfinite(half)) and np.all(np.isfinite(full)) and full.mean() > 0
    se = math.sqrt(half.var(ddof=1) / len(half) + full.var(ddof=1) / len(full))
    assert abs(half.mean() - full.mean()) <= 4 * se + 2.0 ** -11 * full.mean(), (half.mean(), full.mean(), se)
