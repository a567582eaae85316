"""Thin walls in the path pass (opencl/bsdf/thin_dielectric.h through opencl/path/walk.h): a white furnace. A closed
sphere of white thin-walled sheet (Principled Transmission 1, Thin Wall) in a uniform white world (radiance 1): a
white sheet reflects R and passes T = 1 - R (the slab's sums), so every pixel converges to 1 when smooth, and when
rough to 1 within the energy compensation's accuracy (Cycles applies it to both parts, as here). A tinted sheet
(Base Color 0.5) absorbs: its sphere is darker than the world, which tells the harness can see a loss. Shadow rays
pass the smooth sheet (bvh/thin_wall_shadow.h) and BSDF rays find the world through it from the vertex before
(path/thin_wall_emitters.h): counted again where the path goes on through the sheet (the negative control
TEST_THIN_WALL_COUNTED_TWICE), the sphere comes out brighter than the world. The rough case's bound is loose (the
compensation's accuracy), yet it sees a rough sheet whose transmission's pdf is 5 % too small (the negative control
TEST_THIN_TRANSMISSION_PDF_SCALE): its samples through the sheet weigh about 1 / 0.95 too much, and the sphere comes
out brighter than the world by twice the bound (1.09 measured, the bound 1 + 0.047)."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Camera, Environment, Material, Mesh, Renderer, Scene, Settings, look_at
from restircl.scenes.shapes import icosphere

from ..bias_controls import built_with
from .test_glass import BOUNCES, SIZE

BATCHES, FRAMES = 4, 32
THIN_PDF_SCALE = 0.95  # the rough sheet's biased variant: its transmission's pdf 5 % too small


def sphere_mean(roughness: float, colour: float = 1.0) -> tuple[float, float]:
    """The mean over the sphere's central pixels and its standard error over independent stills"""
    sv, st = icosphere(3, 1.0)
    cam = Camera(look_at((0.0, -4.0, 0.0), (0.0, 0.0, 0.0))[None], SIZE, SIZE, lens=50.0)
    sheet = Material("sheet", (colour,) * 3, roughness=roughness, ior=1.5, specular=0.5, transmission=1.0,
                     distribution="ggx", thin_wall=True)
    scene = Scene([Mesh("ball", sv, st, 0)], [sheet], [], cam, environment=Environment(color=(1.0, 1.0, 1.0)),
                  name="thin_wall_furnace")
    s = Settings(method="ris", max_bounces=BOUNCES, diffuse_bounces=BOUNCES, glossy_bounces=BOUNCES,
                 transmission_bounces=BOUNCES, jitter=False)
    imgs = np.stack([Renderer(scene, Settings(**{**s.__dict__, "seed": 7 + b})).render_still(0, samples=FRAMES)
                     .color[..., :3].astype(np.float64) for b in range(BATCHES)])
    assert np.all(np.isfinite(imgs))
    c = SIZE // 2
    per_batch = imgs[:, c - 4:c + 4, c - 4:c + 4].mean(axis=(1, 2, 3))  # well inside the sphere's disk
    return per_batch.mean(), per_batch.std(ddof=1) / np.sqrt(BATCHES)


def test_smooth_white_thin_sphere_in_a_white_world_is_white(device):
    mean, se = sphere_mean(0.0)
    assert abs(mean - 1.0) < 4 * se + 2e-3, (mean, se)


def test_rough_white_thin_sphere_keeps_the_energy(device):
    mean, se = sphere_mean(0.4)
    assert abs(mean - 1.0) < 4 * se + 2e-2, (mean, se)


def test_a_rough_sheet_with_a_wrong_transmission_pdf_misses_the_bound(device, monkeypatch: pytest.MonkeyPatch):
    built_with(monkeypatch, f"TEST_THIN_TRANSMISSION_PDF_SCALE={THIN_PDF_SCALE!r}f")
    mean, se = sphere_mean(0.4)
    assert not abs(mean - 1.0) < 4 * se + 2e-2, (mean, se)


def test_a_tinted_thin_sphere_is_darker(device):
    mean, se = sphere_mean(0.0, 0.5)
    assert mean < 0.8, (mean, se)


def test_light_behind_a_smooth_sheet_counted_twice_is_seen(device, monkeypatch: pytest.MonkeyPatch):
    built_with(monkeypatch, "TEST_THIN_WALL_COUNTED_TWICE")
    mean, se = sphere_mean(0.0)
    assert mean > 1.0 + 4 * se + 2e-3, (mean, se)

