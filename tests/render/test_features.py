"""Leaving out what a scene does not need (DESIGN section 6): the feature flags derived from a scene and its
settings are the ones it needs; a specialised build gives bit-identical images to the general build (same seeds);
the pipeline runs only the passes a frame needs (Frame.stage_ms)."""

import numpy as np
import pytest
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, scenes, translation
from restircl.render.features import ALL_FLAGS

from ..helpers import occluder_scene

W, H = 24, 16
OUTPUTS = ("color", "noisy", "depth", "normal", "vector", "albedo")


def points_only() -> Scene:
    return occluder_scene(W, H)


def meshes_only() -> Scene:
    return scenes.many_lights(width=W, height=H, frames=1, lamps=40, point_lights=0, objects=6)


def area_sun_spot() -> Scene:
    fv, ft = scenes.quad(4, 4)
    bv, bt = scenes.box((0.5, 0.5, 0.7))
    lights = [
        Light("quad", "area", (1.0, 0.8, 0.6), 40.0, translation(-0.7, 0.4, 1.4), size=0.5),
        Light("disk", "area", (0.6, 0.8, 1.0), 30.0, translation(0.8, 0.6, 1.2), shape="DISK", size=0.4),
        Light("sun", "sun", (1.0, 1.0, 0.9), 1.5, look_at((0.4, -0.6, 1.0), (0, 0, 0)), angle=0.05),
        Light("spot", "spot", (1.0, 0.7, 0.7), 120.0, look_at((1.0, -1.0, 1.8), (0.3, 0.0, 0.0)), spot_size=0.8),
    ]
    cam = Camera(look_at((0.0, -3.2, 2.4), (0.0, 0.0, 0.3)), W, H, lens=28.0)
    return Scene([Mesh("floor", fv, ft, 0), Mesh("block", bv + (0.2, 0.1, 0.35), bt, 0)],
                 [Material("grey", (0.7, 0.7, 0.7))], lights, cam, name="area_sun_spot")


def animated_camera() -> Scene:
    scene = area_sun_spot()
    scene.camera.transforms = np.stack([look_at((0.3 * f - 0.4, -3.2, 2.4), (0.0, 0.0, 0.3)) for f in range(4)])
    scene.name = "animated_camera"
    return scene


def still_animation() -> Scene:
    """Four frames of a camera that does not move: nothing to reproject, no motion vectors to compile."""
    scene = area_sun_spot()
    scene.camera.transforms = np.repeat(scene.camera.transforms[:1], 4, axis=0)
    scene.name = "still_animation"
    return scene


def moving_object() -> Scene:
    scene = animated_camera()
    scene.meshes[1].transforms = np.stack([translation(0.15 * f, 0.0, 0.0) for f in range(4)])
    scene.name = "moving_object"
    return scene


def lights_seen() -> Scene:
    """Every light visible to camera rays (Blender makes lights hidden): the camera-light code."""
    scene = area_sun_spot()
    for lt in scene.lights:
        lt.visible_camera = True
    scene.name = "lights_seen"
    return scene


# 2..64 lights (40 points, the four of area_sun_spot): RIS stills pick from the per-pixel table, compiled in for
# every method (the tests render light_array), so that the methods of a scene share one build; 800 emissive
# triangles are too many for the table
AREA_SUN_SPOT = {"HAS_QUAD_LIGHTS", "HAS_DISK_LIGHTS", "HAS_SUN_LIGHTS", "HAS_SPOT_LIGHTS", "HAS_PICK_TABLE"}
SCENES = {
    "points_only": (points_only, {"HAS_SPHERE_LIGHTS", "HAS_PICK_TABLE"}),
    "meshes_only": (meshes_only, {"HAS_TRIANGLE_LIGHTS", "HAS_GLOSSY"}),  # many_lights has glossy objects
    "area_sun_spot": (area_sun_spot, AREA_SUN_SPOT),
    "lights_seen": (lights_seen, AREA_SUN_SPOT | {"HAS_CAMERA_LIGHTS"}),
    "still_animation": (still_animation, AREA_SUN_SPOT),
    "animated_camera": (animated_camera, AREA_SUN_SPOT | {"HAS_MOTION"}),
    "moving_object": (moving_object, AREA_SUN_SPOT | {"HAS_MOTION", "HAS_MOVING_OBJECTS"}),
}


@pytest.mark.parametrize("name", list(SCENES))
def test_derived_flags_are_what_the_scene_needs(device, name):
    make, expected = SCENES[name]
    r = Renderer(make(), Settings(method="light_array"), device)
    on = {k for k, v in r.flags.items() if v}
    assert on == expected, (name, sorted(on))
    assert sorted(r.features) == sorted(k.removeprefix("HAS_").lower() for k in expected)
    g = Renderer(make(), Settings(method="light_array", specialise=False), device)
    assert {k for k, v in g.flags.items() if v and k.startswith("HAS_")} == set(ALL_FLAGS)


def render_sequence(scene: Scene, settings: Settings, device) -> list:
    r = Renderer(scene, settings, device)
    if scene.frames == 1:
        frames = [r.render_frame(0), r.render_frame(0), r.render_still(0, 3)]
    else:
        frames = [r.render_frame(f) for f in range(scene.frames)]
    return frames


@pytest.mark.parametrize("name", list(SCENES))
def test_specialised_and_general_builds_give_identical_images(device, name):
    make = SCENES[name][0]
    for method in ("uniform", "ris", "restir", "reference"):
        s = dict(method=method, seed=17, taa=method == "restir")
        spec = render_sequence(make(), Settings(**s), device)
        gen = render_sequence(make(), Settings(**s, specialise=False), device)
        for k, (a, b) in enumerate(zip(spec, gen, strict=True)):
            for out in OUTPUTS:
                x, y = getattr(a, out), getattr(b, out)
                assert np.array_equal(x, y, equal_nan=False), (name, method, k, out, np.nanmax(np.abs(x - y)))
        assert spec[-1].color[..., :3].max() > 0, (name, method)


def test_passes_run_only_when_needed(device):
    scene = area_sun_spot()
    r = Renderer(scene, Settings(method="restir"), device)
    first = r.render_frame(0, still=True)
    assert set(first.stage_ms) == {"upload", "primary", "initial", "spatial", "shade"}  # no history yet: no temporal
    assert "temporal" in r.render_frame(0, still=True).stage_ms
    assert "taa" in r.render_frame(0).stage_ms  # an animation frame with TAA on
    r = Renderer(scene, Settings(method="restir", taa=False, temporal=False, spatial=False), device)
    for _ in range(2):
        assert set(r.render_frame(0).stage_ms) == {"upload", "primary", "initial", "shade"}
    for method in ("uniform", "light_array", "ris", "reference"):
        r = Renderer(scene, Settings(method=method, taa=False), device)
        for _ in range(2):
            assert set(r.render_frame(0).stage_ms) == {"upload", "primary", "shade"}, method
    # a still render averages: no TAA pass even with taa on
    still = Renderer(scene, Settings(method="light_array"), device).render_still(0, 3)
    assert "taa" not in still.stage_ms


def test_the_methods_of_a_scene_share_one_build(device):
    """Whether RIS stills pick from the per-pixel table is the scene's (its light count), not the method's: every
    method of a scene of four lights gets the same program, light tiles on too, and only the RIS still makes a table
    with it."""
    scene = area_sun_spot()
    rs = {m: Renderer(scene, Settings(method=m, seed=2), device)
          for m in ("uniform", "light_array", "ris", "restir", "reference")}
    for m in ("ris", "restir"):
        rs[f"{m}, tiles"] = Renderer(scene, Settings(method=m, light_tiles="on", seed=2), device)
    assert rs["ris"].flags["HAS_PICK_TABLE"]
    for m, r in rs.items():
        assert r.flags == rs["ris"].flags and r.program is rs["ris"].program, m
        still = r.render_still(0, 2)
        assert np.isfinite(still.color).all() and still.color[..., :3].max() > 0, m
        assert (r.pick_table.buf is not None) == (m == "ris"), m  # the table's buffer is made at its first build


def test_ris_with_one_light_runs_the_single_pick(device):
    """RIS over one light picks that light: with random numbers the pipeline leaves the candidate loop out, so the
    image is the light_array image of the same seed. A Sobol still keeps RIS, whose points come from the sequence
    (tests/render/test_qmc.py::test_one_light_still_draws_its_points_from_sobol): a different image."""
    fv, ft = scenes.quad(4, 4)
    scene = Scene([Mesh("floor", fv, ft, 0)], [Material("grey", (0.7, 0.7, 0.7))],
                  [Light("quad", "area", (1, 1, 1), 40.0, translation(0, 0, 1.2), size=0.6)],
                  Camera(look_at((0, -3, 2), (0, 0, 0)), W, H, lens=28.0))
    ris = Renderer(scene, Settings(method="ris", candidates=32, seed=4, sampler="random"), device).render_still(0, 4)
    la = Renderer(scene, Settings(method="light_array", seed=4), device).render_still(0, 4)
    np.testing.assert_array_equal(ris.color, la.color)
    sobol = Renderer(scene, Settings(method="ris", candidates=32, seed=4), device).render_still(0, 4)
    assert np.isfinite(sobol.color).all() and not np.array_equal(sobol.color, la.color)


def test_animation_of_a_still_camera_accumulates_like_a_still_scene(device):
    """TAA treats an animation whose camera and objects stand still as a still scene: the history is kept whole
    (no clipping to the neighbourhood), so each output is exactly a s_n + (1 - a) f_n-1, a = max(1/n, a_min)."""
    s = Settings(method="light_array", seed=3, jitter=False, alpha_min=0.25)
    r = Renderer(still_animation(), s, device)
    prev = None
    for f in range(4):
        out = r.render_frame(f)
        sample, color = out.noisy, out.color[..., :3]
        if prev is None:
            expect = sample
        else:
            a = np.float32(max(1.0 / (f + 1), s.alpha_min))
            expect = a * sample + (np.float32(1) - a) * prev
        np.testing.assert_allclose(color, expect, rtol=2e-6, atol=1e-7)
        prev = color
