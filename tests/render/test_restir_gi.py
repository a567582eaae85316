"""ReSTIR GI (render/restir_gi.py, opencl/restir_gi/) in animation frames of a still camera (TAA and jitter off):

- its unbiased modes (pairwise MIS, the default, and 1/Z) give, with ReSTIR DI's direct light, a mean over many
  frames equal to the independent numpy path tracer's (tests/render/path_reference.py) within the standard errors of
  both, per pixel and over the image, as tests/render/test_paths.py holds the path pass to it;
- the same harness rejects the spatial and temporal passes without their Jacobian (GI_WITHOUT_JACOBIAN), which
  shows it has the power to see such a bias;
- the biased mode's bias is measured: darker, by an amount bounded below and above;
- what reuse buys: one frame's error against the converged image, with and without reuse;
- a camera cut, a teleport without a cut and every light switching off leave finite images and no stale history.

Frames of one run are correlated (temporal reuse), so the statistics use independent runs (a fresh renderer with its
own seed); at 12x9 pixels the neighbourhood is 4 px and 6 neighbours, so that the spatial pass finds similar
neighbours (the default 30 px disk lies mostly outside such an image)."""

from __future__ import annotations

import math

import numpy as np
import pyopencl as cl
import pytest
from restircl import Light, Renderer, Scene, Settings, translation
from restircl.core import layouts as L

from ..bias_controls import built_with
from ..stats import Z, disagreement
from .path_reference import path_test_scene, trace_paths

# Independent runs, each FRAMES animation frames of the still camera. The frames of a run are correlated and the
# reference's standard error is a large part of sigma, so 128 frames per run were not much sharper than 64: with
# GI_WITHOUT_JACOBIAN (the negative control below) the image means came out 9.5-14.3 standard errors off at 16 x 128
# and 9.9-13.6 at 16 x 64 (seeds 101-116, 2026-12-06; the bound is 4).
BATCHES, FRAMES = 16, 64
REFERENCE_PATHS = 16384
BOUNCES = 3
SMALL = {"gi_radius": 4.0, "gi_spatial_neighbours": 6}


def _settings(**kw) -> Settings:
    return Settings(**{"method": "restir", "max_bounces": BOUNCES, "diffuse_bounces": BOUNCES,
                       "glossy_bounces": BOUNCES, "jitter": False, "taa": False, **SMALL, **kw})


def _runs(scene: Scene, settings: Settings, batches: int = BATCHES, frames: int = FRAMES) -> np.ndarray:
    """(batches, H, W, 3): the mean of each run's frames."""
    means = []
    for b in range(batches):
        r = Renderer(scene, Settings(**{**settings.__dict__, "seed": 101 + b}))
        acc = np.zeros((r.height, r.width, 3))
        for _ in range(frames):
            acc += r.render_frame(0, aovs=False).color[..., :3]
        assert r.last_plan is not None and r.last_plan.gi and r.last_plan.gi_temporal == settings.gi_temporal
        means.append(acc / frames)
    return np.stack(means)


@pytest.fixture(scope="module")
def reference():
    """The numpy path tracer's image of path_test_scene and its standard error (BOUNCES bounces)."""
    ref = trace_paths(path_test_scene(light="both"), BOUNCES, REFERENCE_PATHS, seed=7)
    return ref.cumulative[BOUNCES], ref.cumulative_se[BOUNCES]


def _against_reference(reference, **settings) -> list[str]:
    m = _runs(path_test_scene(light="both"), _settings(**settings))
    expected, ref_se = reference
    se = m.std(axis=0, ddof=1) / math.sqrt(len(m))
    return disagreement(m.mean(axis=0), np.sqrt(se**2 + ref_se**2), expected, batches=len(m), exact_rtol=1e-5)


@pytest.mark.parametrize("bias", ["pairwise", "z_count"])
def test_unbiased_modes_equal_the_reference(device, reference, bias):
    problems = _against_reference(reference, gi_bias_correction=bias)
    assert not problems, problems


def test_spatial_reuse_alone_equals_the_reference(device, reference):
    problems = _against_reference(reference, gi_temporal=False)
    assert not problems, problems


def test_the_harness_rejects_reuse_without_the_jacobian(device, reference, monkeypatch):
    """Negative control: built with GI_WITHOUT_JACOBIAN, a sample moved to another visible point keeps its W
    (and the band test only asks that both sides see it): measured 5.5-6 % too bright over the image (standard
    error 0.5-0.8 %), which the check above must reject."""
    built_with(monkeypatch, "GI_WITHOUT_JACOBIAN=1")
    problems = _against_reference(reference)
    assert any("image means" in p for p in problems), problems


def _image_bias(m: np.ndarray, reference) -> tuple[np.ndarray, np.ndarray]:
    """Relative bias of the image mean per channel and its standard error (runs and reference together)."""
    expected, ref_se = reference
    flat = m.reshape(len(m), -1, 3).mean(axis=1)
    pixels = m.shape[1] * m.shape[2]
    level = expected.reshape(-1, 3).mean(axis=0)
    se = np.sqrt(flat.var(axis=0, ddof=1) / len(m) + (ref_se.reshape(-1, 3) ** 2).sum(axis=0) / pixels**2)
    return flat.mean(axis=0) / level - 1.0, se / level


def test_the_biased_mode_is_darker_by_a_bounded_amount(device, reference):
    """bias_correction none: no visibility in the reuse and M-weighted merges, so a neighbour's sample that x_s is
    hidden from (shaded black by the final visibility ray) or that this pixel's BSDF does not reach still takes its
    share. Measured on this box (3 bounces, 48 runs x 256 frames against our own path pass, 4096 frames x 8 runs,
    2026-12-05): 4.9 % (red), 5.2 %, 5.2 % (blue) too dark, standard errors 0.1 %. Asserted: darker beyond 4
    standard errors, and by 2-9 % (the measured bias +- more than 4 of this test's standard errors, about 0.6 %).
    16 runs of 256 frames: the numpy reference's standard error rules this test's (32 runs: 0.41-0.53 %, 16 runs:
    0.46-0.61 %, bias / se 8.3-11.1 against 6.9-9.8; 16 runs of 128 frames: 0.50-0.86 %, 4.8-9.0; 2026-12-06)."""
    runs = _runs(path_test_scene(light="both"), _settings(gi_bias_correction="none"), BATCHES, 4 * FRAMES)
    bias, se = _image_bias(runs, reference)
    assert np.all(bias + Z * se < 0.0), (bias, se)
    assert np.all((bias > -0.09) & (bias < -0.02)), (bias, se)


def _rel_mse(img: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((img - ref) ** 2 / (ref**2 + 1e-2)))


def test_reuse_lowers_one_frames_error(device, reference):
    """What reuse buys, at one frame each: after 32 frames of a still camera, a frame of ReSTIR GI (temporal and
    spatial) has less than half the error of a frame of paths alone against the converged image (measured, 8 seeds:
    relMSE 0.13 against 0.75, a sixth)."""
    expected, _ = reference
    errors = {}
    for reuse in (True, False):
        e = []
        for seed in range(4):
            r = Renderer(path_test_scene(light="both"), _settings(gi_reuse=reuse, seed=seed))
            for _ in range(32):
                f = r.render_frame(0, aovs=False)
            e.append(_rel_mse(f.color[..., :3], expected))
        errors[reuse] = float(np.mean(e))
    assert errors[True] < 0.5 * errors[False], errors


def _reservoirs(r: Renderer) -> np.ndarray:
    res = np.empty(r.pixels, L.GI_RESERVOIR)
    cl.enqueue_copy(r.device.queue, res, r.history.gi_reservoirs(r.history.prev))
    return res


def test_history_follows_the_camera_and_drops_at_cuts_and_light_switches(device):
    """Two rooms 1000 m apart; the camera orbits in room A (frames 0-5), teleports to room B (6, no cut marker),
    moves there, cuts back to A (9, marked), and every light switches off at frame 11. History survives the orbit
    (reprojected: reservoirs hold several frames), reprojection rejects all of it at the teleport, a cut starts
    over, and with the lights off the frame's estimate is exactly black at once (no stale L_o). Every frame is
    finite."""
    scene = _two_rooms()
    r = Renderer(scene, _settings(gi_spatial_neighbours=2, taa=True, jitter=True))
    mean_m, max_m = [], []
    for f in range(scene.frames):
        out = r.render_frame(f)
        assert np.isfinite(out.color).all() and np.isfinite(out.noisy).all(), f
        assert sum(out.guards.values()) == 0, (f, out.guards)
        plan = r.last_plan
        assert plan is not None and plan.gi
        assert plan.gi_temporal == (f not in (0, 9, 11)), f
        m = _reservoirs(r)["M"]
        mean_m.append(float(m.mean()))
        max_m.append(float(m.max()))
        if f >= 11:  # the frame's own estimate; TAA keeps its colour history across a light switch
            assert np.all(out.noisy == 0), f
    assert mean_m[5] > 3.0, mean_m  # the orbit kept its history
    # without history a reservoir holds its own sample and at most 2 fresh neighbours': the first frame, the
    # teleport (reprojection rejected every pixel), the cut and the light switch
    for f in (0, 6, 9, 11):
        assert max_m[f] <= 3.0, (f, max_m)
    assert max_m[8] > 3.0 and max_m[10] > 3.0, max_m


def _two_rooms() -> Scene:
    """path_test_scene's box twice, the second 1000 m along x, its camera path: an orbit in A, B, A again."""
    a = path_test_scene(24, 18, light="quad")
    far = np.array([1000.0, 0.0, 0.0])
    meshes = a.meshes + [type(m)(m.name + "_b", m.vertices + far, m.triangles, m.material_ids) for m in a.meshes]
    off = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0])
    lights = [Light("panel", "area", (1.0, 0.95, 0.85), 60.0, translation(0.2, 0.1, 2.48), shape="RECTANGLE",
                    size=1.0, size_y=0.8, power_per_frame=off),
              Light("panel_b", "area", (0.9, 0.95, 1.0), 60.0, translation(1000.2, 0.1, 2.48), shape="RECTANGLE",
                    size=1.0, size_y=0.8, power_per_frame=off)]
    cam = a.camera
    assert cam is not None
    base = cam.transforms[0]
    mats = []
    for f in range(13):
        m = base.copy()
        if 6 <= f <= 8:
            m[:3, 3] += far
        m[0, 3] += 0.05 * (f % 6)
        mats.append(m)
    cam = type(cam)(np.stack(mats), cam.width, cam.height, lens=cam.lens, cuts=(9,))
    return Scene(meshes, a.materials, lights, cam, name="two_rooms", frame_count=13)


def test_no_gi_kernels_without_bounces_or_reuse(device):
    scene = path_test_scene()
    assert "gi_initial" not in Renderer(scene, Settings(max_bounces=0)).kernels.k
    assert "gi_initial" not in Renderer(scene, Settings(max_bounces=2, gi_reuse=False)).kernels.k
    r = Renderer(scene, Settings(max_bounces=2))
    assert "gi_initial" in r.kernels.k and "gi_reuse" in r.features
    still = r.render_still(0, samples=2)
    assert "paths" in still.stage_ms and "gi_initial" not in still.stage_ms  # stills keep the path pass


def test_disocclusion_boost_is_taken_only_without_history(device):
    """A pixel without history (its own sample alone, M = 1) takes gi_disocclusion_boost neighbours: spatial reuse
    alone (no pixel has history) merges up to 1 + 8 samples with a boost of 8, never more than 1 + 2 without;
    a boost not above Neighbours changes nothing."""
    scene = path_test_scene(light="both")
    most = {}
    for boost in (0, 2, 8):
        r = Renderer(scene, _settings(gi_temporal=False, gi_spatial_neighbours=2, gi_disocclusion_boost=boost))
        images = [r.render_frame(0, aovs=False).color for _ in range(3)]
        most[boost] = (float(_reservoirs(r)["M"].max()), images)
    assert most[0][0] <= 3.0 < most[8][0] <= 9.0, {k: v[0] for k, v in most.items()}
    assert all(np.array_equal(a, b) for a, b in zip(most[0][1], most[2][1], strict=True))


def test_the_boiling_filter_empties_outliers(device):
    """gi_boiling_filter (biased, animation frames only): at strength 1 every reservoir whose contribution exceeds
    its tile's mean is emptied, so the frame's bounced light falls; the images stay finite."""
    scene = path_test_scene(24, 18, light="both")
    means = {}
    for strength in (0.0, 1.0):
        r = Renderer(scene, _settings(gi_boiling_filter=strength, boiling_mode="contribution", gi_temporal=False))
        out = [r.render_frame(0, aovs=False) for _ in range(8)]
        assert all(np.isfinite(f.color).all() for f in out)
        assert ("gi_boiling" in out[-1].stage_ms) == (strength > 0)
        means[strength] = float(np.mean([f.color[..., :3].mean() for f in out]))
    assert means[1.0] < 0.97 * means[0.0], means
