"""The environment under stress and on its way in: a 1x1 map, an HDRI whose sun is 1e5 times the sky, an all-black
map, NaN / Inf / negative texels (zeroed and counted with one warning naming the world, never in the image),
camera visibility, strengths of 0 and 1e6, a huge map (slow: 16384 x 8192), image files (EXR, Radiance HDR, PNG)
and the scene file. Also: the feature flag leaves the environment out of scenes without one."""

import warnings

import numpy as np
import pytest
from restircl import Environment, Renderer, Scene, SceneError, Settings
from restircl.environment.image import environment_texels, read_radiance_hdr
from restircl.lights import environment
from restircl.lights.device_lights import scene_lights
from restircl.render.features import derive_flags
from restircl.scenes.hdri_sky import sky, sky_map

W, H = 24, 16


def scene_with(env: Environment | None) -> Scene:
    sc = sky(W, H, map_height=16)
    sc.environment = env
    return sc


def frames(scene: Scene, method: str = "restir", count: int = 4, **settings) -> np.ndarray:
    r = Renderer(scene, Settings(method=method, seed=2, **settings))
    return np.stack([r.render_frame(0, still=True).color for _ in range(count)])


@pytest.mark.parametrize("method", ["ris", "restir", "ris_mis_sample"])
def test_sun_1e5_times_the_sky_stays_finite(method):
    img = sky_map(32, 64, sun_scale=1.0)
    img[img.max(axis=2) > 100] = 1e5 * img[0, 0]  # the sun disk: 1e5 x the zenith sky
    extra = {"bsdf_mis_sample": True} if method == "ris_mis_sample" else {}
    out = frames(scene_with(Environment("bright", color=(1, 1, 1), image=img)), method.split("_")[0], **extra)
    assert np.all(np.isfinite(out)) and out[..., :3].mean() > 0


@pytest.mark.parametrize("env", [
    Environment("one_texel", color=(1, 1, 1), image=np.full((1, 1, 3), 0.7, np.float32)),
    Environment("black", color=(1, 1, 1), image=np.zeros((8, 16, 3), np.float32)),
    Environment("zero_strength", color=(1, 1, 1), strength=0.0, image=sky_map(8, 16)),
    Environment("strong", color=(1, 1, 1), strength=1e6, image=sky_map(8, 16)),
], ids=lambda e: e.name)
def test_degenerate_worlds_render_finite(env):
    out = frames(scene_with(env))
    assert np.all(np.isfinite(out))
    if env.name in ("black", "zero_strength"):
        assert np.all(out[..., :3] == 0.0)  # nothing else lights the sky scene
    else:
        assert out[..., :3].min() >= 0 and out[..., :3].mean() > 0


def test_bad_texels_are_zeroed_with_one_warning_naming_the_world():
    img = sky_map(8, 16)
    img[1, 2] = np.nan
    img[2, 3, 1] = np.inf
    img[3, 4, 2] = -5.0
    env = Environment("dirty", color=(1, 1, 1), image=img)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        texels, zeroed = environment_texels(env)
    assert zeroed == 3 and np.all(np.isfinite(texels)) and texels.min() >= 0
    msgs = [str(w.message) for w in caught]
    assert len(msgs) == 1 and "'dirty'" in msgs[0] and "3 texel" in msgs[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = frames(scene_with(env))
    assert np.all(np.isfinite(out))


def test_bad_worlds_are_refused_naming_the_world():
    for env in (Environment("w", strength=-1.0), Environment("w", color=(1, float("nan"), 0)),
                Environment("w", image=np.zeros((4, 4))), Environment("w", path="/no/such/file.exr"),
                Environment("w", rotation=np.ones((3, 3)))):
        with pytest.raises(SceneError, match="world 'w'"):
            scene_with(env).validate()


def test_scene_without_environment_builds_without_its_code():
    flags = derive_flags(scene_lights(scene_with(None), 0).type_set, False, False)
    assert not flags["HAS_ENVIRONMENT"]
    flags = derive_flags(scene_lights(scene_with(Environment()), 0).type_set, False, False)
    assert flags["HAS_ENVIRONMENT"]


def test_without_camera_visibility_the_sky_is_black():
    """The top row of the sky scene sees only the world: black without camera visibility (the surfaces are lit
    the same either way)."""
    env = Environment("hidden", color=(1, 1, 1), image=sky_map(8, 16), visible_camera=False)
    out = frames(scene_with(env), "reference", 1)[0]
    seen = frames(scene_with(Environment("shown", color=(1, 1, 1), image=sky_map(8, 16))), "reference", 1)[0]
    assert np.all(out[0, :, :3] == 0) and np.all(seen[0, :, :3] > 0.1)
    lit = out[..., :3].max(axis=2) > 0
    np.testing.assert_allclose(out[lit], seen[lit], rtol=1e-5)


def test_image_files_load_as_the_array(tmp_path):
    import OpenEXR
    from PIL import Image

    img = sky_map(8, 16, sun_scale=0.01)
    exr = tmp_path / "sky.exr"
    OpenEXR.File({}, {"RGB": img}).write(str(exr))
    np.testing.assert_allclose(environment_texels(Environment(color=(1, 1, 1), path=str(exr)))[0], img, rtol=1e-6)
    png = tmp_path / "sky.png"
    Image.fromarray(np.full((4, 8, 3), 255, np.uint8)).save(png)
    np.testing.assert_allclose(environment_texels(Environment(color=(1, 1, 1), path=str(png)))[0], 1.0)
    # Radiance RGBE, flat scanlines: 0.5 = 128 x 2^(128 - 136)
    hdr = tmp_path / "sky.hdr"
    pix = np.tile(np.array([128, 64, 32, 129], np.uint8), (2 * 3, 1)).reshape(2, 3, 4)
    hdr.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 3\n" + pix.tobytes())
    np.testing.assert_allclose(read_radiance_hdr(hdr), np.tile([1.0, 0.5, 0.25], (2, 3, 1)))


def test_scene_file_keeps_the_environment(tmp_path):
    rot = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    sc = scene_with(Environment("kept", color=(0.5, 1, 1), strength=3.0, image=sky_map(4, 8), rotation=rot,
                                visible_camera=False, strength_per_frame=[1.0, 0.5], interpolation="Linear"))
    sc.save(tmp_path / "s.npz")
    back = Scene.load(tmp_path / "s.npz").environment
    assert back is not None and back.name == "kept" and back.strength == 3.0 and not back.visible_camera
    assert back.interpolation == "Linear"
    assert back.color == (0.5, 1, 1)
    np.testing.assert_array_equal(back.image, sc.environment.image)
    np.testing.assert_array_equal(back.rotation, rot)
    np.testing.assert_array_equal(back.strength_per_frame, [1.0, 0.5])
    sc.environment = None
    sc.save(tmp_path / "none.npz")
    assert Scene.load(tmp_path / "none.npz").environment is None


def test_map_memory_is_what_the_layout_says():
    """The device bytes of a map: 6 per texel (RGB half) or 12 (RGB float32), plus the table (alias: 8 per texel,
    cdf: 4)."""
    env = Environment(color=(1, 1, 1), image=sky_map(16, 32))
    lights = scene_lights(scene_with(env), 0)
    assert lights.environment is not None and lights.environment.stored.fmt == "half"
    assert lights.data.nbytes == environment.data_bytes(16, 32, environment.TABLE_KIND, "half")
    assert environment.data_bytes(8192, 16384, "alias", "float") == 4 * (3 + 2) * 8192 * 16384 + 4 * 2 * 8192
    assert environment.data_bytes(8192, 16384, "cdf", "half") == 4 * (1.5 + 1) * 8192 * 16384 + 4 * (2 * 8192 + 1)
    assert environment.data_bytes(1, 1, "cdf", "half") == 4 * (2 + 2 + 2)  # 3 halves take 2 floats, the cdf 2 + 2


@pytest.mark.slow
def test_16384_by_8192_map_renders():
    img = np.full((8192, 16384, 3), 0.25, np.float32)
    img[4000:4010, 9000:9010] = 5e3
    out = frames(scene_with(Environment("huge", color=(1, 1, 1), image=img)), "ris", 2)
    assert np.all(np.isfinite(out)) and out[..., :3].mean() > 0


def test_strength_per_frame_animates_the_world():
    """At frame 1, a world whose strength_per_frame is (1, 0.5) renders half as bright as one at (1, 1), pixel for
    pixel (the same seeds and frame draw the same samples)."""
    def at_frame_1(per_frame):
        env = Environment("dimming", color=(1, 1, 1), image=sky_map(8, 16), strength_per_frame=per_frame)
        scene = scene_with(env)
        assert scene.has_moving_lights
        return Renderer(scene, Settings(method="reference", seed=2, jitter=False, taa=False)).render_still(
            1, samples=4).color[..., :3]

    half, full = at_frame_1([1.0, 0.5]), at_frame_1([1.0, 1.0])
    assert full.mean() > 0
    np.testing.assert_allclose(half, 0.5 * full, rtol=1e-4, atol=1e-7)
