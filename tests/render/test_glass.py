"""Glass in the path pass (opencl/bsdf/microfacet_dielectric.h through opencl/path/walk.h): a white furnace. A glass
sphere in a uniform white world (radiance 1) with bounces enough for every path to leave it: light is neither made
nor lost by a smooth interface (throughput R + T = 1 at each crossing), so every pixel, sphere or world, converges
to 1; a rough interface of single-scattering GGX may lose a little, at grazing angles most, but never makes light,
and with Multiscatter GGX loses nothing either.
The harness rejects a kernel whose refraction forgets the Fresnel factor (energy made at every crossing)."""

from __future__ import annotations

import math

import numpy as np
from restircl import Camera, Environment, Mesh, Renderer, Scene, Settings, look_at
from restircl.eval.scenes.glass import glass_material
from restircl.scenes.shapes import icosphere

from ..bias_controls import built_with

BATCHES, FRAMES, SIZE = 6, 48, 24
BOUNCES = 64


def furnace(roughness: float, distribution: str) -> Scene:
    sv, st = icosphere(4, 1.0)
    cam = Camera(look_at((0.0, -4.0, 0.0), (0.0, 0.0, 0.0))[None], SIZE, SIZE, lens=50.0)
    glass = glass_material("glass", roughness, distribution=distribution)
    return Scene([Mesh("ball", sv, st, 0)], [glass], [], cam,
                 environment=Environment(color=(1.0, 1.0, 1.0)), name="glass_furnace")


def sphere_mean(roughness: float, distribution: str = "ggx") -> tuple[float, float, float]:
    """The mean over the sphere's pixels, its standard error over independent stills, and the smallest pixel."""
    scene = furnace(roughness, distribution)
    s = Settings(method="ris", max_bounces=BOUNCES, diffuse_bounces=BOUNCES, glossy_bounces=BOUNCES,
                 transmission_bounces=BOUNCES, jitter=False)
    imgs = np.stack([Renderer(scene, Settings(**{**s.__dict__, "seed": 31 + b})).render_still(0, samples=FRAMES)
                     .color[..., :3].astype(np.float64) for b in range(BATCHES)])
    assert np.all(np.isfinite(imgs))
    # the sphere's pixels: those whose camera ray meets it (a ray from the eye within the sphere's angular radius)
    y, x = np.mgrid[0:SIZE, 0:SIZE] + 0.5
    half = SIZE / 2
    tan_r = 1.0 / math.sqrt(4.0**2 - 1.0)
    focal = 50.0 / 36.0 * SIZE  # the lens over Blender's 36 mm sensor, in pixels
    inside = np.hypot(x - half, y - half) < 0.95 * tan_r * focal
    per_batch = imgs[:, inside].mean(axis=(1, 2))
    return per_batch.mean(), per_batch.std(ddof=1) / math.sqrt(BATCHES), imgs.mean(axis=0)[inside].min()


def test_smooth_glass_sphere_in_a_white_world_is_white(device):
    mean, se, _ = sphere_mean(0.0)
    assert abs(mean - 1.0) < 4 * se + 2e-3, (mean, se)


def test_rough_glass_sphere_makes_no_light(device):
    """Roughness 0.3, GGX: no gain beyond the noise; single scattering loses a few percent (at grazing angles up to
    a quarter), not more."""
    mean, se, _ = sphere_mean(0.3)
    assert mean < 1.0 + 4 * se, (mean, se)
    assert mean > 0.9, (mean, se)


def test_rough_multiscatter_glass_sphere_is_white(device):
    """Roughness 0.3, Multiscatter GGX: the energy compensation (upload/glass_tables.py) gives back what single
    scattering loses, so the sphere is white again, to the tables' interpolation."""
    mean, se, _ = sphere_mean(0.3, "multi_ggx")
    assert abs(mean - 1.0) < 4 * se + 5e-3, (mean, se)


def test_the_furnace_rejects_refraction_without_fresnel(device, monkeypatch):
    built_with(monkeypatch, "DIELECTRIC_WITHOUT_FRESNEL_IN_REFRACTION=1")
    mean, se, _ = sphere_mean(0.0)
    assert mean > 1.0 + 4 * se + 2e-3, (mean, se)


def pane_behind_light(roughness: float) -> Scene:
    """A single glass sheet (one quad facing the camera) with an area light behind it shining through it."""
    from restircl import Light
    from restircl.scenes.shapes import quad

    v, t = quad(2.0, 2.0)
    light = Light("behind", "area", (1.0, 1.0, 1.0), 50.0, look_at((0.0, 0.0, -1.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
                  size=1.0)
    cam = Camera(look_at((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0))[None], 16, 16, lens=50.0)
    return Scene([Mesh("pane", v, t, 0)], [glass_material("pane", roughness)], [light], cam, name="pane")


def direct_mean(scene: Scene, method: str, samples: int = 32) -> tuple[float, float]:
    s = Settings(method=method, max_bounces=0, jitter=False)
    m = np.array([Renderer(scene, Settings(**{**s.__dict__, "seed": 5 + b})).render_still(0, samples=samples)
                  .color[..., :3].mean() for b in range(4)])
    return float(m.mean()), float(m.std(ddof=1) / 2.0)


def test_direct_light_reaches_a_rough_pane_from_behind(device):
    """Max Bounces 0: at a rough glass sheet the direct estimators count a light behind it through the refraction
    lobe (evaluated about the flipped normal), RIS and the exhaustive reference alike; smooth glass, which no light
    sample can meet, gets nothing from it."""
    rough = pane_behind_light(0.4)
    ris, ris_se = direct_mean(rough, "ris")
    ref, ref_se = direct_mean(rough, "reference", 512)
    assert ref > 0.02 and abs(ris - ref) < 4 * math.hypot(ris_se, ref_se) + 1e-3 * ref, (ris, ref, ris_se, ref_se)
    smooth, _ = direct_mean(pane_behind_light(0.0), "reference")
    assert smooth < 1e-3 * ref, (smooth, ref)
