"""Cycles' light passes (Settings.light_passes, render/light_passes.py, opencl/film/light_passes.h).

With Cycles' convention (the Direct and Indirect passes divided by their part's colour) the passes of every pixel
recombine to the image: (DiffDir + DiffInd) DiffCol + (GlossDir + GlossInd) GlossCol + (TransDir + TransInd) TransCol
+ Emit + Env = Combined, to
float rounding, for each direct estimator of a still, with and without bounces, and for an animation frame (ReSTIR
DI and ReSTIR GI) against its own sample. Each pass is exactly zero where it must be: the glossy passes of a scene
with only diffuse materials, the indirect ones at Max Bounces 0, the Environment without a world or where the camera
ray hits a surface, the Emission where it sees no emitter. A negative control (a kernel that classifies the bounced
light by the last scatter instead of the first) fails the recombination: on a diffuse pixel whose paths end on a
glossy surface it has glossy light with no glossy colour to carry it. The images without light passes are the same
bit for bit (the passes are compiled out), and the passes reach the EXR writer under Blender's layer names."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.io.images import exr_channels
from restircl.materials.material import Material
from restircl.render import pipeline
from restircl.render.light_passes import divide_by_colour
from restircl.render.passes import PASSES

from .path_reference import path_test_scene

LIGHT = ("diffuse_direct", "diffuse_indirect", "glossy_direct", "glossy_indirect", "glossy_color", "emission",
         "environment")


def _glossy_box(world: tuple[float, float, float] | None = (0.2, 0.25, 0.3)):
    """The test box of tests/render/path_reference.py with a visible area light, a floor with a dielectric specular
    layer over its diffuse part, and a copper-like metal tall block."""
    scene = path_test_scene(24, 18, light="both", world=world, light_visible=True)
    scene.materials[0] = Material("white", (0.75, 0.75, 0.75), specular=0.5, roughness=0.3)
    scene.materials.append(Material("metal", (0.9, 0.6, 0.45), metallic=1.0, roughness=0.25))
    tall = next(m for m in scene.meshes if m.name == "tall")
    tall.material_ids = np.full(len(tall.triangles), len(scene.materials) - 1, np.int32)
    return scene


def recombined(f) -> np.ndarray:
    """The image the passes of frame f add up to."""
    return ((f.diffuse_direct + f.diffuse_indirect) * f.albedo + (f.glossy_direct + f.glossy_indirect) * f.glossy_color
            + (f.transmission_direct + f.transmission_indirect) * f.transmission_color + f.emission + f.environment)


def _mismatch(rec: np.ndarray, image: np.ndarray) -> float:
    """The largest per-pixel difference relative to the pixel's value (float rounding: about 1e-7)."""
    return float(np.max(np.abs(rec - image) / np.maximum(np.abs(image), 1e-3)))


def _still(scene, **kw):
    return Renderer(scene, Settings(light_passes=True, **kw)).render_still(0, samples=8)


@pytest.mark.parametrize(("method", "bounces", "extra"), [
    ("ris", 0, {"bsdf_mis_sample": True}),
    ("ris", 3, {"bsdf_candidates": 2}),
    ("restir", 3, {}),
    ("reference", 2, {}),
    ("light_array", 1, {}),
])
def test_still_passes_recombine_to_combined(device, method, bounces, extra):
    f = _still(_glossy_box(), method=method, max_bounces=bounces, **extra)
    assert _mismatch(recombined(f), f.color[..., :3]) < 1e-5
    # every kind of light is there: this is no identity of zeros
    for name in ("diffuse_direct", "glossy_direct", "emission", "environment", "glossy_color"):
        assert getattr(f, name).max() > 0, name
    assert (f.diffuse_indirect.max() > 0 and f.glossy_indirect.max() > 0) == (bounces > 0)


def test_animation_frame_passes_recombine_to_its_sample(device):
    """Animation frames (ReSTIR DI + ReSTIR GI) write the frame's own sample's passes, before TAA."""
    r = Renderer(_glossy_box(), Settings(method="restir", max_bounces=3, light_passes=True))
    for _ in range(3):
        f = r.render_frame(0)
        assert _mismatch(recombined(f), f.noisy) < 1e-5
    assert r.last_plan is not None and r.last_plan.gi
    assert f.diffuse_indirect.max() > 0 and f.glossy_indirect.max() > 0


def test_passes_are_zero_where_they_must_be(device):
    diffuse_only = _still(path_test_scene(24, 18, light="both"), method="ris", max_bounces=3)
    for name in ("glossy_direct", "glossy_indirect", "glossy_color", "environment", "transmission_direct",
                 "transmission_indirect", "transmission_color"):
        assert not np.any(getattr(diffuse_only, name)), name
    assert diffuse_only.diffuse_indirect.max() > 0
    assert _mismatch(recombined(diffuse_only), diffuse_only.color[..., :3]) < 1e-5
    direct_only = _still(_glossy_box(), method="ris", max_bounces=0)
    assert not np.any(direct_only.diffuse_indirect) and not np.any(direct_only.glossy_indirect)
    # without jitter every sample's camera ray is the one the depth pass shows: with it, a pixel on the box's rim
    # sees both the wall and the world, whichever its last sample met
    box = _still(_glossy_box(), method="ris", max_bounces=1, jitter=False)
    hit = np.isfinite(box.depth)
    assert not np.any(box.environment[hit]) and np.all(box.environment[~hit] > 0)
    lamp = box.emission.max(axis=-1) > 0  # the area light and the emissive patch the camera sees, nothing else
    assert 0 < lamp.sum() < 0.2 * lamp.size and not np.any(box.diffuse_direct[lamp & ~hit])


def test_without_light_passes_the_image_is_the_same(device):
    """The passes are compiled out without the setting, and with it the image is unchanged: to the bit here, as
    both builds run the same arithmetic for the colour."""
    scene = _glossy_box()
    plain = Renderer(scene, Settings(method="ris", max_bounces=2)).render_still(0, samples=4)
    passes = Renderer(scene, Settings(method="ris", max_bounces=2, light_passes=True)).render_still(0, samples=4)
    assert plain.diffuse_direct is None and "light_passes" not in plain.features
    assert "light_passes" in passes.features
    assert np.array_equal(plain.color, passes.color)


def test_classifying_by_the_last_bounce_fails_the_recombination(device, monkeypatch):
    """Negative control: LIGHT_PASSES_BY_LAST_BOUNCE takes the diffuse share of the last scatter. Diffuse pixels
    whose paths end on the metal block then hold glossy indirect light, which no glossy colour carries back."""
    build = pipeline.build_program
    monkeypatch.setattr(pipeline, "build_program", lambda device, flags=None, **kw: build(
        device, flags, extra_options=("-DLIGHT_PASSES_BY_LAST_BOUNCE=1",), **kw))
    f = _still(_glossy_box(), method="ris", max_bounces=3)
    assert _mismatch(recombined(f), f.color[..., :3]) > 1e-2


def test_divide_by_colour_is_cycles_even_division():
    light = np.array([[[0.5, 0.0, 0.3], [1.0, 2.0, 3.0], [0.2, 0.2, 0.2]]], np.float32)
    colour = np.array([[[0.5, 0.0, 0.6], [0.5, 0.5, 0.5], [0.0, 0.0, 0.0]]], np.float32)
    # a channel of colour 0 takes the mean of the pixel's others; a pixel of colour 0 gives 0
    expected = np.array([[[1.0, 0.75, 0.5], [2.0, 4.0, 6.0], [0.0, 0.0, 0.0]]], np.float32)
    assert np.allclose(divide_by_colour(light, colour), expected)


def test_light_passes_reach_the_exr_writer(device):
    f = _still(_glossy_box(), method="ris", max_bounces=1)
    ch = exr_channels(f)
    for layer in ("DiffDir", "DiffInd", "GlossDir", "GlossInd", "GlossCol", "Emit", "Env", "Albedo"):
        assert {f"{layer}.R", f"{layer}.G", f"{layer}.B"} <= set(ch), layer
    assert np.array_equal(ch["GlossDir.G"], f.glossy_direct[..., 1])
    names = {p.attr: (p.blender, p.blender_4) for p in PASSES}
    assert names["diffuse_direct"] == ("Diffuse Direct", "DiffDir") and names["emission"] == ("Emission", "Emit")
    assert names["environment"] == ("Environment", "Env") and names["glossy_color"] == ("Glossy Color", "GlossCol")
    assert all(names[n][0] for n in LIGHT)
