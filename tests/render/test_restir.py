"""ReSTIR DI: the unbiased modes (pairwise MIS, the default, and 1/Z) match the reference; the biased mode's
darkening is measured and bounded; temporal reuse under camera motion keeps no invalid sample; a camera cut resets;
a light switched off stops contributing at once; one ReSTIR frame has far less error than one RIS frame with the
same candidates.

Frames of one ReSTIR run are correlated (temporal reuse), so the statistics use independent runs (fresh renderer,
own seed) and compare run means with the reference within 4 standard errors."""

import numpy as np
import pytest
from restircl import Light, Renderer, Scene, Settings, look_at, scenes, translation

from ..bias_controls import built_with, wrong_pdf
from ..helpers import (
    allowed_outliers,
    batch_stats,
    collect,
    constant,
    luminance,
    mean_and_se,
    mixed_lights_scene,
    occluder_scene,
    print_power,
    rel_mse,
    run_means,
)
from ..stats import weighted_image_bias

W, H = 16, 12
RUNS, FRAMES = 48, 96
# The unbiasedness checks run at two sizes: "quick" in the default suite (half the runs of half the frames, a
# quarter of the reference), "full" behind the slow marker (the figures in the comments below). Both judge by the
# measured standard errors; quick has half of full's resolution for a bias.
SIZES = {"quick": (24, 48, 2048), "full": (RUNS, FRAMES, 8192)}  # runs, frames per run, reference frames
SIZE_PARAMS = [pytest.param("full", marks=pytest.mark.slow), "quick"]
SCENES = {"occluders": occluder_scene, "mixed_lights": mixed_lights_scene}


@pytest.fixture(scope="module")
def references(reference_samples):
    """references[name] (full size) or references[name, size]: batch statistics of the exhaustive sampler
    (rendered once per session: lights/test_tree_estimators.py compares with the same renders)."""

    class Cache(dict):
        def __missing__(self, key):
            name, size = key if isinstance(key, tuple) else (key, "full")
            if (name, size) not in self:
                ref = reference_samples(SCENES[name](W, H), Settings(method="reference", seed=55, jitter=False),
                                        SIZES[size][2])
                dict.__setitem__(self, (name, size), batch_stats(luminance(ref), 32))
            return dict.__getitem__(self, (name, size))

    return Cache()


def assert_matches(runs: np.ndarray, ref: tuple[np.ndarray, np.ndarray], label: str) -> None:
    """Per pixel within 4 standard errors but for the allowed outliers; the image mean, plain and weighted by
    inverse deviation (stats.weighted_image_bias: its standard error is a half to a fifth of the plain one's), within
    4 standard errors. The power of both image checks is printed."""
    lum = luminance(runs)
    a, sa = mean_and_se(lum)
    b, sb = ref
    sigma = np.sqrt(sa**2 + sb**2)
    live = ~constant(sigma, b)
    z = np.abs(a - b)[live] / sigma[live]
    img = lum.mean(axis=(1, 2))
    se_img = np.hypot(img.std(ddof=1) / np.sqrt(len(img)), sb.mean() / np.sqrt(b.size))
    bias_w, se_w = weighted_image_bias(lum, b, sb)
    print_power(f"{label} (plain)", img.mean() / b.mean() - 1.0, se_img / b.mean())
    print_power(f"{label} (weighted)", bias_w, se_w)
    assert (z > 4).sum() <= allowed_outliers(int(live.sum()), len(runs)), (label, "outliers", np.sort(z)[-5:])
    assert abs(img.mean() - b.mean()) <= 4 * se_img, (label, "image means", img.mean(), b.mean())
    assert abs(bias_w) <= 4 * se_w, (label, "weighted image means", bias_w, se_w)


# With 1/Z weights, temporal and spatial reuse together with the default history cap (20x) make runs heavy-tailed
# (a lucky sample persists for tens of frames), which a 4-sigma test over 48 runs cannot judge: 1/Z gets the cap 4x
# there. Pairwise MIS is tested with the default cap (measured at 16x12, 96 frames: relMSE per run 0.014 pairwise
# vs 0.25 for 1/Z on the occluder scene).
CONFIGS = {
    "temporal": dict(spatial=False),
    "spatial": dict(temporal=False),
    "spatiotemporal": dict(),
}


@pytest.mark.parametrize("size", SIZE_PARAMS)
@pytest.mark.parametrize("scene_name", ["occluders", "mixed_lights"])
@pytest.mark.parametrize("config", list(CONFIGS))
@pytest.mark.parametrize("visibility", [True, False])
@pytest.mark.parametrize("bias_correction", ["pairwise", "z_count"])
def test_unbiased_mode_matches_reference(device, references, scene_name, config, visibility, bias_correction,
                                         size):
    if bias_correction == "z_count" and scene_name == "mixed_lights":
        pytest.skip("1/Z is checked on the occluder scene; the default (pairwise) on both")
    scene = occluder_scene(W, H) if scene_name == "occluders" else mixed_lights_scene(W, H)
    cap = dict(m_cap=4.0) if bias_correction == "z_count" and config == "spatiotemporal" else {}
    s = Settings(method="restir", bias_correction=bias_correction, visibility_reuse=visibility, jitter=False,
                 taa=False, seed=3, **CONFIGS[config], **cap)
    runs = run_means(scene, s, SIZES[size][0], SIZES[size][1], device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, references[scene_name, size], f"{scene_name} {config} vis={visibility} {bias_correction}")


@pytest.mark.parametrize("size", SIZE_PARAMS)
def test_unbiased_mode_with_light_tiles_matches_reference(device, references, size):
    """Initial candidates from presampled light tiles (lights/tiles.h; small tiles: 4 x 32 draws per frame for the
    16x12 image's 3 pixel strips), then temporal and spatial reuse: still unbiased."""
    scene = mixed_lights_scene(W, H)
    s = Settings(method="restir", jitter=False, taa=False, seed=8, light_tiles="on", light_tile_count=4,
                 light_tile_size=32)
    runs = run_means(scene, s, SIZES[size][0], SIZES[size][1], device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, references["mixed_lights", size], "mixed_lights light tiles")


@pytest.mark.parametrize("size", SIZE_PARAMS)
@pytest.mark.parametrize("scene_name", ["occluders", "mixed_lights"])
def test_permutation_sampling_stays_unbiased(device, references, scene_name, size):
    """Temporal reuse from a permuted neighbour in a 4x4 block (camera/reproject.h), then spatial reuse: pairwise MIS
    weighs the history at the surface it came from, so the mode stays unbiased."""
    scene = occluder_scene(W, H) if scene_name == "occluders" else mixed_lights_scene(W, H)
    s = Settings(method="restir", jitter=False, taa=False, seed=12, temporal_permutation=True)
    runs = run_means(scene, s, SIZES[size][0], SIZES[size][1], device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, references[scene_name, size], f"{scene_name} permutation")


@pytest.mark.parametrize("size", SIZE_PARAMS)
def test_disocclusion_boost_stays_unbiased(device, references, size):
    """Without temporal reuse no pixel has history, so every pixel takes the boosted neighbour count (8)."""
    scene = occluder_scene(W, H)
    s = Settings(method="restir", jitter=False, taa=False, seed=14, temporal=False, disocclusion_boost=8)
    runs = run_means(scene, s, SIZES[size][0], SIZES[size][1], device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, references["occluders", size], "occluders disocclusion boost")


def test_the_harness_rejects_a_wrong_pdf(device, references, monkeypatch):
    """Negative control at the quick size: initial candidates with a light pdf 2 % too small
    (tests/bias_controls.py) make every pixel's direct light 2 % too bright; assert_matches must reject it."""
    ref = references["occluders", "quick"]
    wrong_pdf(monkeypatch)
    s = Settings(method="restir", jitter=False, taa=False, seed=3)
    runs = run_means(occluder_scene(W, H), s, SIZES["quick"][0], SIZES["quick"][1], device)
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_matches(runs, ref, "occluders pairwise, wrong pdf")


# The biased mode's runs are heavy-tailed (a darkened sample kept for tens of frames): 4x the quick size's runs,
# judged by the weighted image mean, whose standard error (about 0.26 %) is a sixteenth of its bias. Measured with
# seed 5 (2026-12-06): 192 runs -4.12 % +- 0.21 % (z -20), 96 runs -4.45 % +- 0.26 % (z -17, 1.9 standard errors
# from BIASED_BIAS): half the runs widen the bound on its size from 0.84 % to 1.04 %.
BIASED_RUNS = 4 * SIZES["quick"][0]
# measured with the defaults (spatial radius 5 px, disocclusion boost 8, permutation sampling) and the merge counting
# the M of the inputs whose target holds the sample (restir/reuse.h; seeds 5-7: -3.97 %, -4.10 %, -3.84 %, each
# +- 0.12 %); with the plain 1/M and no permutation it was -4.45 % to -4.63 %, under the earlier 30 px and no boost
# -1.1 % to -2.4 %: more neighbours close by keep more samples that are occluded here
BIASED_BIAS = -0.0397


def test_biased_mode_darkens_by_its_measured_amount(device, references):
    """M-weighted reuse without shadow rays counts neighbours that cannot see the sample: it darkens contact shadows, by
    BIASED_BIAS over the image (weighted by inverse deviation). Asserted: darker beyond 4 standard errors (the sign),
    and within 4 of them of BIASED_BIAS (the size). The check of the unbiased modes (assert_matches) rejects it."""
    scene = occluder_scene(W, H)
    s = Settings(method="restir", bias_correction="none", jitter=False, taa=False, seed=5)
    runs = run_means(scene, s, BIASED_RUNS, SIZES["quick"][1], device)
    b, sb = references["occluders", "quick"]
    bias, se = weighted_image_bias(luminance(runs), b, sb)
    print(f"biased mode: relative bias of the weighted image mean {bias:+.4f} +- {se:.4f}")
    assert bias < -4 * se, (bias, se)
    assert abs(bias - BIASED_BIAS) < 4 * se, (bias, se)
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_matches(runs, (b, sb), "biased mode")


def moving_camera_scene() -> Scene:
    scene = occluder_scene(W, H)
    a = look_at((0.0, -4.0, 3.0), (0.0, 0.0, 0.3))
    b = look_at((2.5, -2.5, 1.2), (-0.5, 0.5, 0.4))  # low, from the side: other surfaces, other occlusions
    scene.camera.transforms = np.stack([a, b])
    return scene


def test_temporal_reuse_after_camera_motion_keeps_no_invalid_sample(device):
    scene = moving_camera_scene()
    outs = []
    for k in range(RUNS):
        r = Renderer(scene, Settings(method="restir", jitter=False, taa=False, seed=100 + k), device)
        for _ in range(6):
            r.render_frame(0)
        outs.append(r.render_frame(1).noisy)
    runs = np.stack(outs).astype(np.float64)
    still = occluder_scene(W, H)
    still.camera.transforms = moving_camera_scene().camera.transforms[1:2]
    # the exhaustive reference's standard error is a small part of sigma = hypot(se_runs, se_ref): measured with
    # 1024 frames, se_ref / se_runs was 0.010 (median pixel), 0.035 (99th percentile), so at 512 frames it is
    # below 0.05 and sigma within 0.13 % of se_runs alone; more frames would not sharpen the test
    ref = collect(still, Settings(method="reference", seed=56, jitter=False), 512, device)
    assert_matches(runs, batch_stats(luminance(ref), 32), "after camera motion")


def test_camera_cut_resets_history(device):
    scene = moving_camera_scene()
    scene.camera.cuts = (1,)
    r = Renderer(scene, Settings(method="restir", seed=1), device)
    f0 = r.render_frame(0)
    f0b = r.render_frame(0)
    assert "temporal" in f0b.stage_ms and "temporal" not in f0.stage_ms
    f1 = r.render_frame(1)
    assert "temporal" not in f1.stage_ms
    # TAA restarted: the output is the new sample itself
    np.testing.assert_array_equal(f1.color[..., :3], f1.noisy)
    f2 = r.render_frame(1)
    assert "temporal" in f2.stage_ms


def switch_off_scene(second_light: bool) -> Scene:
    fv, ft = scenes.quad(4, 4)
    from restircl import Camera, Material, Mesh

    lights = [Light("switched", "point", (1, 1, 1), 200.0, translation(0.5, 0.0, 1.0), radius=0.1,
                    power_per_frame=np.array([1.0, 0.0, 0.0]))]
    if second_light:
        lights.append(Light("steady", "area", (1, 0.8, 0.6), 30.0, translation(-0.8, 0.3, 1.2), size=0.5))
    cam = Camera(look_at((0, -3.0, 2.5), (0, 0, 0)), W, H, lens=30.0)
    return Scene([Mesh("floor", fv, ft, 0)], [Material("grey", (0.7, 0.7, 0.7))], lights, cam, frame_count=3)


def test_light_switched_off_stops_contributing_at_once(device):
    r = Renderer(switch_off_scene(False), Settings(method="restir", seed=2), device)
    for _ in range(5):
        assert r.render_frame(0).noisy.max() > 0
    f = r.render_frame(1)
    assert np.all(f.noisy == 0.0)
    # with a second, steady light the first frame after the switch is an unbiased image of the steady light alone
    outs = []
    for k in range(RUNS):
        r = Renderer(switch_off_scene(True), Settings(method="restir", jitter=False, taa=False, seed=300 + k), device)
        for _ in range(6):
            r.render_frame(0)
        outs.append(r.render_frame(1).noisy)
    steady = switch_off_scene(True)
    steady.lights = steady.lights[1:]
    ref = collect(steady, Settings(method="reference", seed=57, jitter=False), 2048, device)
    assert_matches(np.stack(outs).astype(np.float64), batch_stats(luminance(ref), 32), "after switch-off")


def test_one_restir_frame_beats_one_ris_frame_on_many_lights(device):
    scene = scenes.many_lights(width=96, height=54, frames=1)
    ref = collect(scene, Settings(method="ris", candidates=32, seed=9, jitter=False), 384, device).mean(axis=0)
    ris = collect(scene, Settings(method="ris", candidates=8, seed=10, jitter=False), 4, device)
    restir = collect(scene, Settings(method="restir", candidates=8, seed=11, jitter=False, taa=False), 4, device,
                     warmup=8)
    e_ris = np.mean([rel_mse(x, ref) for x in ris])
    e_restir = np.mean([rel_mse(x, ref) for x in restir])
    print(f"relMSE of one frame: ris {e_ris:.4f}, restir {e_restir:.4f}, ratio {e_ris / e_restir:.1f}")
    assert e_restir < 0.5 * e_ris


def test_dimmed_light_keeps_history_switched_light_drops_it(device):
    scene = switch_off_scene(True)
    scene.lights[0].power_per_frame = np.array([1.0, 1.5, 0.0])
    r = Renderer(scene, Settings(method="restir", seed=4), device)
    r.render_frame(0)
    assert "temporal" in r.render_frame(1).stage_ms  # 1.5x: below the light_change_ratio of 2
    assert "temporal" not in r.render_frame(2).stage_ms  # switched off
    assert "temporal" in r.render_frame(2).stage_ms


def test_static_lights_reuse_the_stored_target(device, monkeypatch):
    """With last frame's light records, temporal reuse takes p_prev of last frame's sample from the target its
    reservoir stored instead of evaluating it again: the same number, so the images are bit-identical to a
    renderer that re-evaluates it every frame (as it must when the lights changed)."""
    scene = occluder_scene()
    assert not scene.has_moving_lights and not scene.has_moving_objects
    outs = []
    for force_changed in (False, True):
        r = Renderer(scene, Settings(method="restir", candidates=4), device)
        if force_changed:
            ds = r.device_scene
            upload = ds.upload

            def upload_and_mark(frame, last_frame, ds=ds, upload=upload):
                upload(frame, last_frame)
                ds.lights_changed = True

            monkeypatch.setattr(ds, "upload", upload_and_mark)
        outs.append(np.stack([r.render_frame(0, still=False).noisy for _ in range(4)]))
    assert outs[0].max() > 0
    np.testing.assert_array_equal(outs[0], outs[1])


@pytest.mark.parametrize("size", SIZE_PARAMS)
def test_fresh_candidates_stay_unbiased(device, references, size):
    """Spatial only with one neighbour and no boost: every pixel is fresh and about half are lonely (no similar
    neighbour: render/test_lonely_fresh.py), and those merge 8 more candidates (restir/lonely_fresh.h)."""
    s = Settings(method="restir", jitter=False, taa=False, seed=15, temporal=False, spatial_neighbours=1,
                 disocclusion_boost=0, fresh_candidates=8)
    runs = run_means(occluder_scene(W, H), s, SIZES[size][0], SIZES[size][1], device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, references["occluders", size], "occluders fresh candidates")


def test_the_harness_rejects_fresh_candidates_left_out_of_m(device, references, monkeypatch):
    """Negative control: the same with the extra candidates merged but not counted in M
    (TEST_LONELY_FRESH_M_KEPT, tests/bias_controls.py) makes the lonely pixels too bright."""
    built_with(monkeypatch, "TEST_LONELY_FRESH_M_KEPT")
    s = Settings(method="restir", jitter=False, taa=False, seed=15, temporal=False, spatial_neighbours=1,
                 disocclusion_boost=0, fresh_candidates=8)
    runs = run_means(occluder_scene(W, H), s, SIZES["quick"][0], SIZES["quick"][1], device)
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_matches(runs, references["occluders", "quick"], "occluders fresh candidates, M kept")
