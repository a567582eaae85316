"""Presampled light tiles (opencl/lights/tiles.h): every tile entry is a light-array draw (the light's record copied
bit for bit, its pick pdf slots / M, lights drawn in proportion to it); RIS and ReSTIR over tile candidates stay
unbiased (render/test_estimators.py, render/test_restir.py); "auto" uses tiles only for the RIS-based methods and only
from LIGHT_TILES_AUTO lights."""

import numpy as np
import pyopencl as cl
import pytest
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, scenes, translation
from restircl.render import plan

from ..helpers import mixed_lights_scene
from ..stats import pooled_chi2

TILES = dict(light_tiles="on", light_tile_count=8, light_tile_size=64)


def tile_contents(r: Renderer) -> tuple[np.ndarray, np.ndarray]:
    s = r.settings
    n = s.light_tile_count * s.light_tile_size
    info = np.zeros((n, 2), np.int32)
    rec = np.zeros(n, r.lights.records.dtype)
    cl.enqueue_copy(r.device.queue, info, r.tile_info)
    cl.enqueue_copy(r.device.queue, rec, r.tile_rec)
    return info, rec


def test_tile_entries_are_light_array_draws(device):
    r = Renderer(mixed_lights_scene(16, 12), Settings(method="ris", seed=4, **TILES), device)
    la = r.light_array
    counts = np.zeros(len(r.lights), np.int64)
    previous = None
    for _ in range(48):
        r.render_frame(0, still=True)
        assert r.light_tiles_used
        info, rec = tile_contents(r)
        light = info[:, 0]
        assert light.min() >= 0 and light.max() < len(r.lights)
        # the record is the light's record, bit for bit; the pdf is the light array's
        np.testing.assert_array_equal(rec.view(np.uint32), r.lights.records[light].view(np.uint32))
        np.testing.assert_array_equal(info[:, 1].view(np.float32), la.pdf[light])
        if previous is not None:
            assert not np.array_equal(light, previous)  # fresh draws every frame
        previous = light
        counts += np.bincount(light, minlength=len(r.lights))
    assert counts[la.pdf == 0].sum() == 0
    stat, p, dof = pooled_chi2(counts, la.pdf)
    assert dof >= 5 and p > 1e-4, (stat, p, dof)


def above_and_below_scene() -> Scene:
    """A floor lit by one point light above it; a second light of the same power lies below it (no contribution)."""
    fv, ft = scenes.quad(4, 4)
    lights = [Light("above", "point", (1, 1, 1), 100.0, translation(0.0, 0.0, 1.0)),
              Light("below", "point", (1, 1, 1), 100.0, translation(0.0, 0.0, -1.0))]
    cam = Camera(look_at((0.0, -3.0, 2.0), (0.0, 0.0, 0.0)), 16, 12, lens=30.0)
    return Scene([Mesh("floor", fv, ft, 0)], [Material("floor", (0.7, 0.7, 0.7))], lights, cam, name="above_below")


@pytest.mark.parametrize("method", ["ris", "restir"])
def test_candidates_come_from_the_tiles(device, method):
    """With one tile of one entry, every candidate of a frame is that entry's light: the image is black exactly in
    the frames whose tile holds the light below the floor. (Drawn from the light array instead, 4 candidates per
    pixel would bring the light above into almost every pixel of every frame.)"""
    s = Settings(method=method, candidates=4, temporal=False, spatial=False, seed=12, light_tiles="on",
                 light_tile_count=1, light_tile_size=1)
    r = Renderer(above_and_below_scene(), s, device)
    seen = set()
    for _ in range(24):
        f = r.render_frame(0, still=True)
        light = int(tile_contents(r)[0][0, 0])
        seen.add(light)
        lit = f.noisy.max() > 0
        assert lit == (light == 0), (light, f.noisy.max())
    assert seen == {0, 1}


def test_auto_uses_tiles_for_ris_methods_with_many_lights(device, monkeypatch):
    scene = mixed_lights_scene(16, 12)
    for method in ("ris", "restir", "light_array", "uniform", "reference"):
        r = Renderer(scene, Settings(method=method, seed=1), device)
        r.render_frame(0)
        assert not r.light_tiles_used  # a handful of lights: below LIGHT_TILES_AUTO
        assert "tiles" not in r.render_frame(0).stage_ms
    monkeypatch.setattr(plan, "LIGHT_TILES_AUTO", 4)  # the threshold plan_frame reads
    for method, used in (("ris", True), ("restir", True), ("light_array", False), ("reference", False)):
        r = Renderer(scene, Settings(method=method, seed=1), device)
        f = r.render_frame(0)
        assert r.light_tiles_used == used, method
        assert ("tiles" in f.stage_ms) == used
        assert np.all(np.isfinite(f.color))
    r = Renderer(scene, Settings(method="restir", light_tiles="off", seed=1), device)
    r.render_frame(0)
    assert not r.light_tiles_used


def test_tile_settings_are_checked():
    for bad in (dict(light_tiles="yes"), dict(light_tile_count=0), dict(light_tile_size=0),
                dict(light_tile_size=1 << 20), dict(light_tile_count=4096, light_tile_size=2048)):
        with pytest.raises(ValueError):
            Settings(**bad).validate()
