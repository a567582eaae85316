"""Regression: every built-in scene and method renders the images recorded from the code before the refactor.

Each case renders a few animation frames (TAA, reprojection, temporal reuse) and a short still accumulation (the two
half buffers, the second ReSTIR chain, the error estimate) with fixed seeds, and compares SHA-256 hashes of the
colour, noisy and AOV buffers with tests/data/regression_images.json. Where the OpenCL device is the one the hashes
were recorded on (same device name and driver version) the images must be bit-identical. On another CPU, PoCL's code
generation may round differently (vector width, math library), so there the AOVs are compared with the stored ones
(tests/data/regression_images.npz) to a tolerance at floating-point level, and the colours by their noise:
resampling turns a last-bit difference into another pick, so a colour image of another CPU is another realisation of
the same estimator. tests/data/regression_colours.npz holds each case's still colour (seed 7) and a tolerance
measured where it was recorded: the relative mean absolute difference (of x / (1 + x), the 2 % of pixels that differ
most left out) of two still images of the same case with two different seeds, over the six pairs of seeds 7-10,
their mean plus 4 of their standard deviations. A still of another device that differs from the stored one by more
than that is not another realisation of the same estimator. (Exact images, the reference method's, get the same
noise bound, which is far above float rounding: they are checked loosely there.) Record the colours anew on any
device with RESTIRCL_RECORD_COLOURS=1.

Tolerances recorded: 0.002-0.03 for the reference method and RIS on the small scenes, up to 0.17 for ReSTIR on
occluders, 0.4-1.3 on many_lights (40 lamps and 16 points, 20 samples: its stills are that noisy), where the check
catches only a broken render. test_the_colour_check_rejects_a_wrong_pdf shows what it catches on cornell_box.

With `-m slow`, every case also renders bit-identical buffers with BVH leaf packets on and off (on any device).

Record anew (only when an image is meant to change): RESTIRCL_RECORD_REGRESSION=1 pytest
tests/render/test_regression_images.py
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import numpy as np
import pytest
from restircl import Renderer, Settings, scenes
from restircl.bvh import packets as bvh_packets

from ..bias_controls import wrong_pdf
from ..helpers import mixed_lights_scene, occluder_scene

DATA = Path(__file__).parents[1] / "data"
HASHES = DATA / "regression_images.json"
IMAGES = DATA / "regression_images.npz"
COLOURS = DATA / "regression_colours.npz"
RECORD = os.environ.get("RESTIRCL_RECORD_REGRESSION") == "1"
RECORD_COLOURS = os.environ.get("RESTIRCL_RECORD_COLOURS") == "1"
NOISE_SEEDS = (7, 8, 9, 10)
TRIM = 0.02  # share of the pixels left out of the colour comparison (relative_difference)

SCENES = {
    "many_lights": lambda: scenes.many_lights(width=40, height=24, frames=4, lamps=40, point_lights=16, objects=8),
    "cornell_box": lambda: scenes.cornell_box(width=32, height=32),
    "moving_box": lambda: scenes.moving_box(width=40, height=30, frames=4),
    "mixed_lights": lambda: mixed_lights_scene(32, 24),
    "occluders": lambda: occluder_scene(32, 24),
}

CONFIGS: dict[str, dict] = {
    "uniform": {"method": "uniform"},
    "light_array": {"method": "light_array"},
    "ris": {"method": "ris", "candidates": 4},
    "reference": {"method": "reference"},
    "restir": {"method": "restir", "candidates": 4},
    "restir_biased": {"method": "restir", "bias_correction": "none", "visibility_reuse": False},
    "restir_zcount": {"method": "restir", "bias_correction": "z_count", "spatial_passes": 2},
    "restir_novis": {"method": "restir", "visibility_reuse": False, "spatial_neighbours": 5},
    "ris_tiles": {"method": "ris", "light_tiles": "on", "light_tile_count": 4, "light_tile_size": 64},
    "restir_tiles": {"method": "restir", "light_tiles": "on", "light_tile_count": 4, "light_tile_size": 64},
    "restir_general": {"method": "restir", "specialise": False},
    "restir_notaa": {"method": "restir", "taa": False, "temporal": False, "jitter": False},
}

# Settings whose default may change on purpose without touching the code the images check: pinned to the value the
# images were recorded with, since the colours can be re-recorded only on the device that recorded them
PINNED: dict = {"spatial_neighbours": 3}

# the configurations every scene renders; the rest run on mixed_lights (every light type) and many_lights
CORE = ("uniform", "light_array", "ris", "reference", "restir")
CASES = [(s, c) for s in SCENES for c in CONFIGS if c in CORE or s in ("mixed_lights", "many_lights")]


def _device_key(device) -> str:
    d = device.device
    return f"{d.name.strip()} | {d.driver_version.strip()} | {d.platform.version.strip()}"


def _render(scene_name: str, config: str, device, seed: int = 7) -> dict[str, np.ndarray]:
    scene = SCENES[scene_name]()
    settings = Settings(seed=seed, **{**PINNED, **CONFIGS[config]})
    r = Renderer(scene, settings, device)
    out: dict[str, np.ndarray] = {}
    for f in range(min(scene.frames, 3)):
        fr = r.render_frame(f)
        out[f"frame{f}.color"] = fr.color
        out[f"frame{f}.noisy"] = np.ascontiguousarray(fr.noisy)
    for aov in ("depth", "normal", "vector", "albedo"):
        out[f"aov.{aov}"] = getattr(fr, aov)
    r.reset()
    still = r.render_still(0, samples=20)
    out["still.color"] = still.color
    out["still.error_estimate"] = np.array([np.nan if still.error_estimate is None else still.error_estimate])
    return {k: np.ascontiguousarray(v, dtype=np.float32) for k, v in out.items()}


def _hash(a: np.ndarray) -> str:
    return hashlib.sha256(a.tobytes()).hexdigest()[:24]


@pytest.fixture(scope="module")
def recorded(device):
    if RECORD:
        return {"device": _device_key(device), "hashes": {}, "images": {}}
    if not HASHES.exists():
        pytest.fail(f"{HASHES} is missing: record it with RESTIRCL_RECORD_REGRESSION=1")
    data = json.loads(HASHES.read_text())
    with np.load(IMAGES) as z:
        data["images"] = {k: z[k] for k in z.files}
    with np.load(COLOURS) as z:
        data["colours"] = {k: z[k] for k in z.files}
    return data


@pytest.mark.parametrize(("scene_name", "config"), CASES, ids=[f"{s}-{c}" for s, c in CASES])
def test_images_unchanged(scene_name, config, device, recorded):
    images = _render(scene_name, config, device)
    prefix = f"{scene_name}/{config}/"
    if RECORD:
        for k, v in images.items():
            recorded["hashes"][prefix + k] = _hash(v)
            if k.startswith("aov."):
                recorded["images"][prefix + k] = v
        return
    same_device = recorded["device"] == _device_key(device)
    for k, v in images.items():
        key = prefix + k
        assert key in recorded["hashes"], f"no recorded image {key}"
        if same_device:
            assert _hash(v) == recorded["hashes"][key], f"{key} is not bit-identical to the recorded image"
        elif k.startswith("aov."):  # geometry only: equal to rounding on any device
            ref = recorded["images"][key]
            assert np.array_equal(np.isfinite(ref), np.isfinite(v)), key
            both = np.isfinite(ref) & np.isfinite(v)
            assert np.allclose(v[both], ref[both], rtol=1e-4, atol=1e-5), f"{key} differs from the recording"
    if not same_device:
        # resampling amplifies the last bit of a difference into another pick: colours compare by their noise
        stored, tolerance = recorded["colours"][prefix + "still.color"], recorded["colours"][prefix + "tolerance"]
        d = relative_difference(images["still.color"], stored)
        print(f"{prefix}still.color: relative difference {d:.4g}, tolerance {float(tolerance):.4g}")
        assert d <= tolerance, f"{prefix}still.color differs by {d:.4g} (relative), more than its noise {tolerance}"


def relative_difference(a: np.ndarray, b: np.ndarray) -> float:
    """Mean absolute difference of a and b per pixel (colour channels summed), relative to the mean of b, after
    x / (1 + x) per channel and without the TRIM share of pixels that differ most: the lamps the camera sees in
    many_lights (tens above the lit surfaces, 13 of its 960 pixels) land in other pixels under another jitter and
    would otherwise make 87 % of the difference, leaving a tolerance that any image meets."""
    a, b = a[..., :3].astype(np.float64), b[..., :3].astype(np.float64)
    a, b = a / (1.0 + np.abs(a)), b / (1.0 + np.abs(b))
    per_pixel = np.sort(np.abs(a - b).sum(axis=-1).ravel())
    kept = per_pixel[: len(per_pixel) - int(TRIM * len(per_pixel))]
    return float(kept.mean() / max(np.abs(b).sum(axis=-1).mean(), 1e-30))


def noise_tolerance(stills: list[np.ndarray]) -> float:
    """Mean plus 4 standard deviations of the relative difference over every pair of the stills."""
    d = [relative_difference(a, b) for i, a in enumerate(stills) for b in stills[i + 1:]]
    return float(np.mean(d) + 4 * np.std(d, ddof=1))


def test_the_colour_check_rejects_a_wrong_pdf(device, recorded, monkeypatch):
    """Negative control of the comparison other CPUs get: cornell_box's RIS still with a light pdf 5 % too small
    (tests/bias_controls.py) is further from the stored still than its noise tolerance (measured 0.033 against
    0.023; mixed_lights' RIS, 0.004 against 0.018, would need more than 20 % on its bright, exact pixels)."""
    if RECORD:
        pytest.skip("recording")
    wrong_pdf(monkeypatch, 0.95)
    key = "cornell_box/ris/"
    still = _render("cornell_box", "ris", device)["still.color"]
    d = relative_difference(still, recorded["colours"][key + "still.color"])
    assert d > recorded["colours"][key + "tolerance"], d


@pytest.mark.skipif(not RECORD_COLOURS, reason="recording the colours only with RESTIRCL_RECORD_COLOURS=1")
def test_record_colours(device):
    out = {}
    for scene_name, config in CASES:
        stills = [_render(scene_name, config, device, seed)["still.color"] for seed in NOISE_SEEDS]
        out[f"{scene_name}/{config}/still.color"] = stills[0]
        out[f"{scene_name}/{config}/tolerance"] = np.array(noise_tolerance(stills))
    np.savez_compressed(COLOURS, **out)


@pytest.mark.slow
@pytest.mark.parametrize(("scene_name", "config"), CASES, ids=[f"{s}-{c}" for s, c in CASES])
def test_images_unchanged_by_leaf_packets(scene_name, config, device, monkeypatch):
    """Leaf packets on and off (bvh.packets.ENABLED: the packet test or the one-by-one leaf test, each on the
    leaf size bvh.packets.leaf_max gives it): every buffer bit for bit the same. Unlike the recorded hashes, this
    holds on any device."""
    images = {}
    for packets in (False, True):
        monkeypatch.setattr(bvh_packets, "ENABLED", packets)
        images[packets] = _render(scene_name, config, device)
    assert images[False].keys() == images[True].keys()
    differ = [k for k, v in images[False].items() if _hash(v) != _hash(images[True][k])]
    assert differ == [], f"differ between leaf packets on and off: {differ}"


def test_zz_write_recording(device, recorded):
    """Runs after the cases (pytest keeps file order): writes the recording when asked to."""
    if not RECORD:
        pytest.skip("recording only with RESTIRCL_RECORD_REGRESSION=1")
    DATA.mkdir(exist_ok=True)
    HASHES.write_text(json.dumps({"device": recorded["device"], "hashes": recorded["hashes"]}, indent=0,
                                 sort_keys=True) + "\n")
    np.savez_compressed(IMAGES, **recorded["images"])
