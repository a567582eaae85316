"""The add-on registers and unregisters cleanly in a plain bpy process, and its settings reach restircl."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402
from restircl.settings.spec import declared  # noqa: E402

from .test_blender_support import (  # noqa: E402
    ensure_registered,
    guard_engine,
    needs_renderer,
    read_exr_passes,
    render_to,
)

pytestmark = pytest.mark.blender


def test_register_unregister_register():
    addon = ensure_registered()
    sc = scenes.new_scene(8, 8)
    sc.render.engine = "RESTIRCL"
    assert sc.render.engine == "RESTIRCL"
    assert sc.restircl.method == "restir"
    assert bpy.context.view_layer.restircl.use_pass_noisy_direct
    assert "RESTIRCL" in bpy.types.DATA_PT_EEVEE_light.COMPAT_ENGINES
    cycles_paths, cycles_sampling = bpy.types.CYCLES_RENDER_PT_light_paths, bpy.types.CYCLES_RENDER_PT_sampling
    assert "RESTIRCL" in cycles_paths.COMPAT_ENGINES and "CYCLES" in cycles_paths.COMPAT_ENGINES
    assert "RESTIRCL" not in cycles_sampling.COMPAT_ENGINES  # the set Cycles' panels share is left alone

    addon.unregister()
    try:
        assert not hasattr(bpy.types.Scene, "restircl")
        assert "RESTIRCL" not in bpy.types.DATA_PT_EEVEE_light.COMPAT_ENGINES
        assert cycles_paths.COMPAT_ENGINES is cycles_sampling.COMPAT_ENGINES == {"CYCLES"}  # inherited again
        assert not hasattr(bpy.types, "RESTIRCL_PT_light_paths")
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
    from restircl_blender.properties import make_settings

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
    s = make_settings(restircl, p)
    assert (s.method, s.candidates, s.temporal, s.spatial_neighbours, s.spatial_radius) == ("ris", 5, False, 4, 12.0)
    assert (s.bias_correction, s.m_cap, s.taa, s.alpha_min, s.seed, s.light_tiles) == ("none", 7.0, False, 0.25, 9,
                                                                                         "off")
    assert set(p.settings_kwargs()) == set(restircl.Settings.names())  # every Settings field, nothing else


def _scene_settings():
    from restircl_blender.properties import SCENE_SETTINGS

    return SCENE_SETTINGS


def test_properties_are_generated_from_the_table():
    """Label, description, default, choices and range of each property are the table's; ints within a C int."""
    ensure_registered()
    from restircl import Settings
    from restircl_blender.properties import INT_MAX, INT_MIN

    rna = bpy.types.Scene.bl_rna.properties["restircl"].fixed_type.properties
    assert {d.name for d in declared(Settings)} <= set(rna.keys())
    for d in _scene_settings():
        prop = rna[d.name]
        assert (prop.name, prop.description) == (d.spec.label, d.spec.description), d.name
        if d.spec.choices:
            items = sorted(d.spec.choices, key=lambda c: c.number)
            assert [(i.identifier, i.name, i.description, i.value) for i in prop.enum_items] == [
                (c.id, c.label, c.description, c.number) for c in items], d.name
            assert prop.default == d.default
            continue
        assert prop.default == pytest.approx(d.default), d.name
        r = d.spec.range
        if r is None:
            continue
        lo = r.lowest() if r.off is None else min(r.lowest(), r.off)
        hi = r.highest()
        if d.kind is int:
            lo, hi = max(lo, INT_MIN), INT_MAX if hi is None else min(hi, INT_MAX)
        assert prop.hard_min == lo, d.name
        if hi is not None:
            assert prop.hard_max == hi, d.name
        if d.spec.soft_max is not None:
            assert prop.soft_max == pytest.approx(d.spec.soft_max, rel=1e-7), d.name


def test_every_value_the_addon_allows_at_its_limits_validates():
    """At each property's hard min and max (the other settings at their defaults; those limited together with it at
    their minimum) restircl accepts the settings: Blender no longer offers values that stop the render."""
    restircl = pytest.importorskip("restircl")
    ensure_registered()
    from restircl import Settings
    from restircl.settings.table import JOINT_LIMITS
    from restircl_blender.properties import make_settings

    sc = scenes.new_scene(8, 8)
    p = sc.restircl
    rna = p.bl_rna.properties
    numbers = [d for d in declared(Settings) if d.spec.range is not None]
    for d in numbers:
        for end in ("hard_min", "hard_max"):
            for other in numbers:
                setattr(p, other.name, other.default)
            for group in JOINT_LIMITS:
                if d.name in group:
                    for name in group:
                        if name != d.name:
                            setattr(p, name, rna[name].hard_min)
            setattr(p, d.name, getattr(rna[d.name], end))
            make_settings(restircl, p).validate()
    for d in numbers:
        setattr(p, d.name, d.default)


class _Layout:
    """Records what a panel's draw() puts in its layout."""

    def __init__(self, drawn: list) -> None:
        self.drawn, self.active, self.use_property_split, self.use_property_decorate = drawn, True, False, True

    def column(self, **_kw):
        return _Layout(self.drawn)

    row = column

    def prop(self, owner, name, **_kw):
        assert hasattr(owner, name), name
        self.drawn.append(name)

    def label(self, text: str = "", **_kw):
        self.drawn.append(("label", text))


def test_panels_draw_every_setting_once():
    ensure_registered()
    from restircl.render.passes import PASSES
    from restircl_blender import ui

    sc = scenes.new_scene(8, 8)
    context = type("Context", (), {"scene": sc, "view_layer": sc.view_layers[0], "engine": "RESTIRCL"})
    drawn: list[str] = []
    for cls in ui.CLASSES:
        panel = type("P", (), {"layout": _Layout(drawn), "settings_panel": getattr(cls, "settings_panel", ""),
                               "header": getattr(cls, "header", None)})
        cls.draw_header(panel, context)
        cls.draw(panel, context)
    toggles = [p.blender_toggle.rpartition(".")[2] for p in PASSES if p.blender_toggle]
    # a setting of no panel is set by the add-on itself (light_passes: from the view layer's pass toggles)
    panelled = [d.name for d in _scene_settings() if d.spec.panel is not None]
    assert sorted(x for x in drawn if isinstance(x, str)) == sorted(panelled + toggles)


def test_the_panel_says_why_the_core_refuses_light_tiles():
    """Tile Size 65536 is in its own range but, with the default 128 tiles, 8,388,608 entries exceed the core's
    4,194,304: the Light Sampling panel marks both values and shows the core's message; within the limit, nothing."""
    ensure_registered()
    from restircl_blender import properties, ui

    sc = scenes.new_scene(8, 8)
    p = sc.restircl
    drawn: list = []

    def draw() -> list:
        drawn.clear()
        ui.draw_settings(_Layout(drawn), p, properties.SCENE_SETTINGS, "lights")
        return [x[1] for x in drawn if isinstance(x, tuple)]

    assert p.light_tile_count == 128 and draw() == []
    p.light_tile_size = 65536
    labels = draw()
    assert len(labels) == 1 and "8388608 light tile entries, more than 4194304" in labels[0], labels
    assert ui.refusal(p)[1] == ("light_tile_count", "light_tile_size")
    p.light_tile_count = 64  # 64 x 65536 = 4,194,304: accepted
    assert draw() == [] and ui.refusal(p) is None
    p.light_tile_count, p.light_tile_size = 128, 1024


def test_every_pass_reaches_blender():
    """register_passes names every pass of the list (with its toggle on) and write_result fills each."""
    ensure_registered()
    import numpy as np
    from restircl.render.passes import PASSES, blender_name
    from restircl_blender.passes import register_passes, toggle_owner
    from restircl_blender.render_result import write_result

    sc = scenes.new_scene(4, 3)
    vl = sc.view_layers[0]
    for p in PASSES:
        if p.blender_toggle is not None:
            owner, name = toggle_owner(vl, p.blender_toggle)
            setattr(owner, name, True)

    class Rp:
        def __init__(self, name, channels):
            self.name, self.channels, self.rect = name, channels, None

    class FakeEngine:
        def __init__(self):
            self.passes = []

        def register_pass(self, scene, layer, name, channels, chan_id, kind):
            self.passes.append(Rp(name, channels))

        def begin_result(self, *args, layer=None):
            return type("Result", (), {"layers": [type("Layer", (), {"passes": self.passes})]})

        def end_result(self, result):
            pass

    fake = FakeEngine()
    register_passes(fake, sc, vl)  # Denoise off: no Noisy Image pass, as in Cycles
    assert "Noisy Image" not in [rp.name for rp in fake.passes]
    sc.restircl.denoise = True
    fake = FakeEngine()
    register_passes(fake, sc, vl)
    sc.restircl.denoise = False
    names = [blender_name(p, bpy.app.version) for p in PASSES]
    assert [rp.name for rp in fake.passes] == names
    assert ("Diffuse Color" if bpy.app.version >= (5, 0, 0) else "DiffCol") in names  # the albedo, as Cycles'
    assert blender_name(next(p for p in PASSES if p.attr == "albedo"), (4, 2, 0)) == "DiffCol"
    frame = type("Frame", (), {p.attr: np.full((3, 4, len(p.channels)), k + 1.0, np.float32)
                               for k, p in enumerate(PASSES)})
    frame.depth = np.full((3, 4), np.inf, np.float32)
    write_result(fake, frame, 4, 3, vl, False)
    for k, (p, rp) in enumerate(zip(PASSES, fake.passes, strict=True)):
        assert rp.rect is not None and rp.rect.shape == (12, len(p.channels)), p.blender
        if p.attr != "color":
            expected = p.miss if p.miss is not None else k + 1.0
            assert np.all(rp.rect == np.float32(expected)), p.blender


def test_device_list_never_raises():
    ensure_registered()
    from restircl_blender import engine

    labels = engine.device_list()
    assert labels and all(isinstance(x, str) for x in labels)


@needs_renderer
def test_albedo_is_the_diffuse_colour_pass_cycles_writes(tmp_path):
    """F12 with Diffuse Color on writes the albedo as that pass, equal to what Cycles writes for the same scene."""
    import math

    import numpy as np

    ensure_registered()
    sc = scenes.new_scene(24, 16, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.6, 0.4)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.diffuse_material("Red", (0.7, 0.2, 0.1)), location=(0.3, 0, 0.4),
               rotation=(0, 0, math.radians(30)))
    scenes.light("POINT", "Point", (-1.0, -0.5, 1.5), energy=60.0)
    scenes.camera((0.0, -4.0, 2.5), (0.0, 0.3, 0.3), lens=28.0)
    sc.view_layers[0].use_pass_diffuse_color = True
    sc.restircl.samples = 2
    render_to(sc, tmp_path / "ours.exr")
    scenes.cycles_direct_only(sc, samples=4, threads=2)
    render_to(sc, tmp_path / "cycles.exr")
    name = "Diffuse Color" if bpy.app.version >= (5, 0, 0) else "DiffCol"
    ours, cyc = read_exr_passes(tmp_path / "ours.exr")[name], read_exr_passes(tmp_path / "cycles.exr")[name]
    assert ours.shape == cyc.shape == (16, 24, 3)
    assert np.median(np.abs(ours - cyc)) < 0.01 and ours.max() > 0.3


def test_a_value_between_off_and_the_range_moves_to_the_nearest_allowed():
    """Blender's min/max cannot say "0 (off) or above 1": a Light Change Ratio typed into that gap moves to the
    nearest value restircl accepts, so the panel offers no value that stops the render."""
    ensure_registered()
    p = scenes.new_scene(8, 8).restircl
    try:
        p.light_change_ratio = 0.9
        assert 1.0 < p.light_change_ratio < 1.0 + 1e-6
        p.light_change_ratio = 0.2
        assert p.light_change_ratio == 0.0
        p.light_change_ratio = 3.0
        assert p.light_change_ratio == 3.0
    finally:
        p.light_change_ratio = 2.0


@needs_renderer
def test_a_setting_out_of_range_is_an_error_report_naming_it(tmp_path, monkeypatch):
    """A value that reached the property without its update callback (a script writing the ID property) and that
    restircl refuses is a report, not a crash caught by the engine's last-resort handler."""
    crashes = guard_engine(monkeypatch)
    sc = scenes.new_scene(8, 6, engine="RESTIRCL")
    scenes.quad("Floor", 4.0, 4.0, scenes.diffuse_material("Floor"))
    scenes.light("POINT", "Point", (0.0, 0.0, 1.5), energy=20.0)
    scenes.camera((0.0, -3.0, 2.0), (0.0, 0.0, 0.0))
    sc.restircl["light_change_ratio"] = 0.5  # the ID property itself: no update callback runs
    try:
        with pytest.raises(RuntimeError, match="light_change_ratio"):
            render_to(sc, tmp_path / "x.exr")
    finally:
        sc.restircl.light_change_ratio = 2.0
    assert not crashes


def test_uses_nodes_on_this_release_without_deprecation_warnings():
    """compat.uses_nodes reads use_nodes only where it is not deprecated (lights from 5.1, materials and worlds
    from 5.0) and says whether the node tree shades the data-block."""
    import warnings

    from restircl_blender import compat

    scenes.new_scene(8, 8)
    blocks = (bpy.data.lights.new("L", "POINT"), bpy.data.materials.new("M"), bpy.data.worlds.new("W"))
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        for block in blocks:
            prop = block.bl_rna.properties["use_nodes"]
            if getattr(prop, "is_deprecated", False):  # (no such attribute before 5.0)
                assert compat.uses_nodes(block) == (block.node_tree is not None), block
                continue
            block.use_nodes = True
            assert compat.uses_nodes(block), block
            block.use_nodes = False
            assert not compat.uses_nodes(block), block
    assert "--python-version 3.11" in compat.import_error_hint((4, 2, 0))
    assert "--python-version" not in compat.import_error_hint((4, 2, 13))
