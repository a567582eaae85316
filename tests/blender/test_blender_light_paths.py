"""Blender's Light Paths drive restircl's bounces: with Cycles' settings in the scene (the Cycles add-on, enabled in
every default Blender) F12 renders and the viewport take them from scene.cycles (material previews from the preview
scene's, as Cycles does), values
restircl refuses are moved into its range with a warning, Light Paths restircl does not apply yet are reported, and
Cycles' Light Paths panels show for the RESTIRCL engine in place of restircl's own (shown without Cycles)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import (  # noqa: E402
    guard_engine,
    needs_renderer,
    read_exr_passes,
    record_engine,
    render_to,
)

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _engine_guard(monkeypatch):
    crashes = guard_engine(monkeypatch)  # registers the add-on
    yield
    assert not crashes, "the engine hit an unexpected exception"


def small_scene(width: int = 16, height: int = 12):
    sc = scenes.new_scene(width, height, engine="RESTIRCL")
    scenes.quad("Floor", 6.0, 6.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("Red", (0.8, 0.2, 0.1)), location=(0.3, 0, 0.4))
    scenes.light("POINT", "Point", (-1.0, -0.5, 1.5), energy=60.0)
    scenes.camera((0.0, -4.0, 2.0), (0.0, 0.5, 0.4), lens=28.0)
    sc.restircl.samples = 1
    return sc


def set_light_paths(sc) -> None:
    """Cycles' Light Paths away from their defaults, and restircl's own set otherwise (they must not be used)."""
    c = sc.cycles
    c.max_bounces, c.diffuse_bounces, c.glossy_bounces, c.min_light_bounces = 3, 2, 1, 1
    c.sample_clamp_indirect = 5.0
    c.sample_clamp_direct = 7.0
    c.use_light_tree = False  # Cycles applies its light threshold only without the light tree
    c.light_sampling_threshold = 0.25
    p = sc.restircl
    p.max_bounces, p.diffuse_bounces, p.glossy_bounces, p.min_light_bounces = 7, 6, 5, 4
    p.clamp_indirect, p.light_threshold, p.clamp_direct = 50.0, 0.5, 40.0


def assert_cycles_light_paths(s) -> None:
    got = (s.max_bounces, s.diffuse_bounces, s.glossy_bounces, s.min_light_bounces, s.clamp_indirect, s.clamp_direct)
    assert got == (3, 2, 1, 1, 5.0, 7.0)
    assert s.light_threshold == pytest.approx(0.25)


# ---- the mapping -------------------------------------------------------------------------------------------


def test_without_cycles_settings_restircl_keeps_its_own():
    from restircl_blender import light_paths

    assert light_paths.read(SimpleNamespace()) == ({}, [])


def test_values_outside_restircl_range_are_clamped_with_a_warning():
    """Settings a script (or another release's Cycles) may hold beyond what restircl accepts: the nearest value it
    accepts, one warning naming each; nothing raises."""
    from restircl import Settings
    from restircl_blender import light_paths

    cycles = SimpleNamespace(max_bounces=5000, diffuse_bounces=-3, glossy_bounces=2, min_light_bounces=0,
                             sample_clamp_indirect=-1.0, light_sampling_threshold=math.nan, use_light_tree=False,
                             sample_clamp_direct=-2.0)
    values, messages = light_paths.read(SimpleNamespace(cycles=cycles))
    assert values == {"max_bounces": 1024, "diffuse_bounces": 0, "glossy_bounces": 2, "min_light_bounces": 0,
                      "clamp_direct": 0.0, "clamp_indirect": 0.0, "light_threshold": 0.0}
    assert len(messages) == 5
    for prop, used in (("max_bounces", "1024"), ("diffuse_bounces", "0"), ("sample_clamp_indirect", "0.0"),
                       ("light_sampling_threshold", "0.0")):
        assert any(prop in m and m.endswith(f"{used} is used") for m in messages), (prop, messages)
    Settings(**values).validate()


def test_a_release_without_a_property_keeps_restircl_setting():
    from restircl_blender import light_paths

    cycles = SimpleNamespace(max_bounces=2, volume_bounces=0)
    assert light_paths.read(SimpleNamespace(cycles=cycles)) == ({"max_bounces": 2}, [])


def test_settings_kwargs_take_cycles_light_paths_and_threshold_follows_the_light_tree():
    sc = small_scene()
    set_light_paths(sc)
    kw = sc.restircl.settings_kwargs()
    assert (kw["max_bounces"], kw["diffuse_bounces"], kw["glossy_bounces"], kw["min_light_bounces"]) == (3, 2, 1, 1)
    assert kw["clamp_indirect"] == 5.0 and kw["light_threshold"] == pytest.approx(0.25) and kw["clamp_direct"] == 7.0
    assert kw["method"] == sc.restircl.method  # the rest is restircl's own
    sc.cycles.use_light_tree = True
    assert sc.restircl.settings_kwargs()["light_threshold"] == 0.0


# ---- every path that makes Settings ------------------------------------------------------------------------


@needs_renderer
def test_f12_renderer_gets_cycles_light_paths(tmp_path, monkeypatch):
    from restircl_blender import engine

    sc = small_scene()
    set_light_paths(sc)
    reports, _stats = record_engine(monkeypatch)
    render_to(sc, tmp_path / "f12.exr")
    assert_cycles_light_paths(engine._SESSIONS[(sc.name, sc.view_layers[0].name)].renderer.settings)
    assert not [m for m in reports if "Light Paths" in m], reports  # all of them applied: nothing to say
    sc.cycles.max_bounces = 1  # a Light Paths edit is a new renderer with it
    render_to(sc, tmp_path / "f12b.exr")
    assert engine._SESSIONS[(sc.name, sc.view_layers[0].name)].renderer.settings.max_bounces == 1


@needs_renderer
def test_viewport_session_gets_cycles_light_paths():
    from restircl_blender import viewport

    sc = small_scene()
    set_light_paths(sc)
    engine = SimpleNamespace(viewport=None)
    viewport.view_update(engine, None, bpy.context.evaluated_depsgraph_get())
    try:
        session = engine.viewport.session
        assert session is not None, engine.viewport.message
        assert_cycles_light_paths(session.settings)
        sc.cycles.max_bounces = 2  # a new key: the session starts over with it
        viewport.view_update(engine, None, bpy.context.evaluated_depsgraph_get())
        assert engine.viewport.session is not session and engine.viewport.session.settings.max_bounces == 2
    finally:
        viewport.free(engine)


@needs_renderer
def test_material_preview_gets_the_preview_scene_light_paths(monkeypatch):
    """A material preview takes its Light Paths from Cycles' settings of Blender's preview scene (fewer bounces,
    none diffuse), as Cycles renders previews, not from the user's scene (whose other settings it takes)."""
    import restircl
    from restircl_blender import preview

    seen, preview_paths = [], []
    real_renderer, real_preview = restircl.Renderer, preview.render_preview

    def spy_renderer(scene, settings, *args, **kwargs):
        seen.append(settings)
        return real_renderer(scene, settings, *args, **kwargs)

    def spy_preview(engine, depsgraph, *args):
        c = depsgraph.scene.cycles
        preview_paths.append((c.max_bounces, c.diffuse_bounces, c.glossy_bounces, c.min_light_bounces,
                              c.sample_clamp_indirect, 0.0 if c.use_light_tree else c.light_sampling_threshold))
        return real_preview(engine, depsgraph, *args)

    sc = small_scene()
    set_light_paths(sc)
    sc.restircl.preview_samples = 1
    sc.restircl.candidates = 5
    monkeypatch.setattr(restircl, "Renderer", spy_renderer)
    monkeypatch.setattr(preview, "render_preview", spy_preview)
    icon = scenes.preview_icon(scenes.diffuse_material("LightPathsPreview", (0.7, 0.5, 0.3)), "RESTIRCL")
    assert np.all(np.isfinite(icon))
    assert seen and preview_paths
    s = seen[-1]
    got = (s.max_bounces, s.diffuse_bounces, s.glossy_bounces, s.min_light_bounces, s.clamp_indirect,
           s.light_threshold)
    assert got == pytest.approx(preview_paths[-1])
    assert preview_paths[-1][:5] != (3, 2, 1, 1, 5.0)  # the preview scene's differ from the user's
    assert s.candidates == 5  # the rest is the user's scene's


# ---- warnings in the render's report ---------------------------------------------------------------------


@needs_renderer
def test_f12_reports_clamped_and_unapplied_light_paths(tmp_path, monkeypatch):
    sc = small_scene()
    sc.cycles.max_bounces = 1
    sc.cycles["min_light_bounces"] = 5000  # the ID property itself: beyond Cycles' own limit (and restircl's)
    sc.cycles.sample_clamp_direct = 2.0  # applied: not reported
    sc.cycles.volume_bounces = 3
    reports, _stats = record_engine(monkeypatch)
    render_to(sc, tmp_path / "warned.exr")
    assert np.all(np.isfinite(read_exr_passes(tmp_path / "warned.exr")["Combined"]))
    ours = [m for m in reports if "Light Paths" in m]
    assert len(ours) == 2, reports
    assert any("min_light_bounces" in m and "1024 is used" in m for m in ours), ours
    assert not any("Clamp Direct" in m for m in ours), ours
    assert sum("Volume bounces" in m and "not applied" in m for m in ours) == 1, ours
    assert all(m.startswith("restircl: ") for m in ours)
    sc.cycles.sample_clamp_direct = 0.0  # back at Cycles' default: nothing to report
    sc.cycles.volume_bounces = 0
    sc.cycles.min_light_bounces = 0
    reports.clear()
    render_to(sc, tmp_path / "quiet.exr")
    assert not [m for m in reports if "Light Paths" in m], reports


# ---- panels ------------------------------------------------------------------------------------------------


def test_cycles_light_paths_panels_show_for_restircl_and_ours_without_cycles():
    sc = small_scene()
    ours = bpy.types.RESTIRCL_PT_light_paths
    shown = ("CYCLES_RENDER_PT_light_paths", "CYCLES_RENDER_PT_light_paths_max_bounces",
             "CYCLES_RENDER_PT_light_paths_clamping")
    for engine in ("RESTIRCL", "CYCLES"):
        ctx = SimpleNamespace(engine=engine, scene=sc)
        for name in shown:
            assert getattr(bpy.types, name).poll(ctx), (name, engine)
        assert not ours.poll(ctx), engine  # Cycles' panels hold the settings
    restircl_ctx = SimpleNamespace(engine="RESTIRCL", scene=sc)
    for name in ("CYCLES_RENDER_PT_light_paths_caustics", "CYCLES_RENDER_PT_light_paths_fast_gi",
                 "CYCLES_RENDER_PT_sampling", "CYCLES_RENDER_PT_film"):
        assert not getattr(bpy.types, name).poll(restircl_ctx), name  # not restircl's
    no_cycles = SimpleNamespace(restircl=sc.restircl)  # a scene of a Blender without the Cycles add-on
    assert ours.poll(SimpleNamespace(engine="RESTIRCL", scene=no_cycles))
    assert not ours.poll(SimpleNamespace(engine="CYCLES", scene=no_cycles))
    assert not ours.poll(SimpleNamespace(engine="BLENDER_EEVEE", scene=no_cycles))


# ---- end to end --------------------------------------------------------------------------------------------


@needs_renderer
def test_bounces_brighten_a_closed_box(tmp_path):
    """A closed room lit by an area light just below the ceiling, facing down: with Max Bounces 0 the ceiling gets
    no light (the light faces away from it), with 2 the light the walls and the floor send back reaches it and
    brightens the whole image."""
    sc = scenes.new_scene(40, 30, engine="RESTIRCL")
    scenes.box("Room", (4.0, 4.0, 3.0), scenes.diffuse_material("White", (0.8, 0.8, 0.8)), location=(0, 0, 1.5),
               inward=True)
    scenes.box("Block", (0.8, 0.8, 1.2), scenes.diffuse_material("Red", (0.8, 0.1, 0.1)), location=(0.6, 0.8, 0.6))
    lamp = scenes.light("AREA", "Lamp", (0.0, 0.0, 2.9), energy=200.0, shape="SQUARE", size=0.8)
    lamp.visible_camera = False
    scenes.camera((0.0, -1.9, 1.5), (0.0, 1.0, 1.6), lens=16.0)
    sc.restircl.samples = 16
    images = {}
    for bounces in (0, 2):
        sc.cycles.max_bounces = bounces
        render_to(sc, tmp_path / f"b{bounces}.exr")
        images[bounces] = read_exr_passes(tmp_path / f"b{bounces}.exr")["Combined"][..., :3]
        assert np.all(np.isfinite(images[bounces])), bounces
    direct, bounced = images[0], images[2]
    print(f"mean direct {direct.mean():.4f}, with 2 bounces {bounced.mean():.4f}")
    assert bounced.mean() > 1.2 * direct.mean() > 0.0
    ceiling = slice(0, 4)  # the top rows see the ceiling, which the light does not face
    assert direct[ceiling].mean() < 0.05 * bounced[ceiling].mean()
