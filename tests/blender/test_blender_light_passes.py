"""Cycles' light passes through the add-on: the view layer's own toggles (use_pass_diffuse_direct, ...) turn them
on in the renderer (Settings.light_passes) and register them with Blender's names; an F12 render writes them into
the Render Result, where they recombine to Combined as Cycles' do; without a toggle on, the renderer compiles them
out and the Render Result has none."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import guard_engine, needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

W, H = 40, 28
TOGGLES = ("use_pass_diffuse_direct", "use_pass_diffuse_indirect", "use_pass_diffuse_color", "use_pass_glossy_direct",
           "use_pass_glossy_indirect", "use_pass_glossy_color", "use_pass_emit", "use_pass_environment")


@pytest.fixture(autouse=True)
def _addon(monkeypatch):
    crashes = guard_engine(monkeypatch)
    yield
    assert not crashes, "the engine hit an unexpected exception (caught by its last-resort handler)"


def _scene():
    sc = scenes.new_scene(W, H, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.principled_material("Shiny", (0.8, 0.3, 0.2)), location=(0.3, 0, 0.4))
    scenes.light("AREA", "Area", (1.0, 0.0, 2.2), energy=80.0, shape="DISK", size=0.8)
    scenes.quad("Lamp", 0.6, 0.3, scenes.emission_material("Glow", (1.0, 0.7, 0.4), 6.0), location=(0, 1.0, 1.8),
                facing_down=True)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    sc.cycles.max_bounces = 2  # the add-on reads the Light Paths from Cycles' settings
    sc.restircl.method = "ris"
    sc.restircl.samples = 4
    return sc


def test_toggles_turn_the_light_passes_on():
    import restircl
    from restircl_blender.passes import light_passes_on
    from restircl_blender.properties import make_settings, render_kwargs

    sc = _scene()
    vl = sc.view_layers[0]
    assert not light_passes_on(vl) and not make_settings(restircl, sc.restircl, view_layer=vl).light_passes
    vl.use_pass_diffuse_color = True  # the albedo comes from the G-buffer: no light passes needed for it
    assert not light_passes_on(vl)
    vl.use_pass_glossy_indirect = True
    assert light_passes_on(vl) and make_settings(restircl, sc.restircl, view_layer=vl).light_passes
    assert render_kwargs(sc.restircl)["light_passes"] is False  # the viewport and previews: no view layer


def test_f12_writes_light_passes_that_recombine(tmp_path):
    sc = _scene()
    vl = sc.view_layers[0]
    for name in TOGGLES:
        setattr(vl, name, True)
    vl.use_pass_z = True
    render_to(sc, tmp_path / "passes.exr")
    p = read_exr_passes(tmp_path / "passes.exr")
    five = bpy.app.version >= (5, 0, 0)
    names = dict(zip(("dd", "di", "dc", "gd", "gi", "gc", "emit", "env"),
                     ("Diffuse Direct", "Diffuse Indirect", "Diffuse Color", "Glossy Direct", "Glossy Indirect",
                      "Glossy Color", "Emission", "Environment") if five else
                     ("DiffDir", "DiffInd", "DiffCol", "GlossDir", "GlossInd", "GlossCol", "Emit", "Env"), strict=True))
    for key, name in names.items():
        assert name in p and p[name].shape == (H, W, 3), (key, sorted(p))
    q = {key: p[name].astype(np.float64) for key, name in names.items()}
    rec = (q["dd"] + q["di"]) * q["dc"] + (q["gd"] + q["gi"]) * q["gc"] + q["emit"] + q["env"]
    combined = p["Combined"][..., :3]
    assert np.max(np.abs(rec - combined) / np.maximum(np.abs(combined), 1e-3)) < 1e-4
    assert q["gd"].max() > 0 and q["gi"].max() > 0 and q["di"].max() > 0 and q["emit"].max() > 0
    assert not np.any(q["env"])  # the scene's world is black


def test_without_toggles_there_are_no_light_passes(tmp_path):
    sc = _scene()
    render_to(sc, tmp_path / "plain.exr")
    p = read_exr_passes(tmp_path / "plain.exr")
    assert not ({"Diffuse Direct", "DiffDir", "Glossy Indirect", "GlossInd", "Emission", "Emit"} & set(p))
    assert math.isfinite(float(p["Combined"].mean()))
