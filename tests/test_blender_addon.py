"""The add-on registers and unregisters cleanly in a plain bpy process, and its settings reach restircl."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")

from .test_blender_support import ensure_registered, scenes  # noqa: E402

pytestmark = pytest.mark.blender


def test_register_unregister_register():
    addon = ensure_registered()
    sc = scenes.new_scene(8, 8)
    sc.render.engine = "RESTIRCL"
    assert sc.render.engine == "RESTIRCL"
    assert sc.restircl.method == "restir"
    assert bpy.context.view_layer.restircl.use_pass_noisy_direct
    assert "RESTIRCL" in bpy.types.DATA_PT_EEVEE_light.COMPAT_ENGINES

    addon.unregister()
    try:
        assert not hasattr(bpy.types.Scene, "restircl")
        assert "RESTIRCL" not in bpy.types.DATA_PT_EEVEE_light.COMPAT_ENGINES
        assert not hasattr(bpy.types, "RESTIRCL_PT_sampling")
        with pytest.raises(TypeError):
            sc.render.engine = "RESTIRCL"
    finally:
        addon.register()
    sc.render.engine = "RESTIRCL"
    assert sc.render.engine == "RESTIRCL"
    # handlers are registered once, even after re-registering
    from restircl_blender import _on_render_done

    assert list(bpy.app.handlers.render_complete).count(_on_render_done) == 1


def test_panels_only_for_our_engine():
    ensure_registered()
    sc = scenes.new_scene(8, 8)

    class Ctx:
        engine = "CYCLES"

    for name in ("RESTIRCL_PT_sampling", "RESTIRCL_PT_reuse", "RESTIRCL_PT_taa", "RESTIRCL_PT_device",
                 "RESTIRCL_PT_passes"):
        panel = getattr(bpy.types, name)
        assert panel.bl_space_type == "PROPERTIES"
        Ctx.engine = "CYCLES"
        assert not panel.poll(Ctx)
        Ctx.engine = "RESTIRCL"
        assert panel.poll(Ctx)
    assert bpy.types.RESTIRCL_PT_sampling.bl_context == "render"
    del sc


def test_settings_reach_restircl():
    restircl = pytest.importorskip("restircl")
    if not hasattr(restircl, "Settings"):
        pytest.skip("restircl.Settings is not available")
    ensure_registered()
    from restircl_blender import engine

    sc = scenes.new_scene(8, 8)
    p = sc.restircl
    p.method = "ris"
    p.candidates = 5
    p.temporal = False
    p.spatial_neighbours = 4
    p.spatial_radius = 12.0
    p.bias_correction = "none"
    p.m_cap = 7.0
    p.taa = False
    p.alpha_min = 0.25
    p.seed = 9
    p.light_tiles = "off"
    s = engine.make_settings(restircl, p)
    assert (s.method, s.candidates, s.temporal, s.spatial_neighbours, s.spatial_radius) == ("ris", 5, False, 4, 12.0)
    assert (s.bias_correction, s.m_cap, s.taa, s.alpha_min, s.seed, s.light_tiles) == ("none", 7.0, False, 0.25, 9,
                                                                                         "off")
    # every Blender setting is a Settings field
    from restircl_blender.properties import SETTINGS_KEYS

    assert set(SETTINGS_KEYS) <= set(restircl.Settings.__dataclass_fields__)


def test_methods_match_renderer():
    restircl = pytest.importorskip("restircl")
    pipeline = pytest.importorskip("restircl.pipeline")
    from restircl_blender.properties import BIAS_MODES, LIGHT_TILES, METHODS

    assert {m[0] for m in METHODS} == set(pipeline.METHODS)
    assert {b[0] for b in BIAS_MODES} == set(pipeline.BIAS_CORRECTIONS)
    assert {t[0] for t in LIGHT_TILES} == set(pipeline.LIGHT_TILES)
    assert f"{pipeline.LIGHT_TILES_AUTO:,} lights" in LIGHT_TILES[0][2]  # the panel's tooltip names the threshold
    del restircl


def test_device_list_never_raises():
    ensure_registered()
    from restircl_blender import engine

    labels = engine.device_list()
    assert labels and all(isinstance(x, str) for x in labels)
