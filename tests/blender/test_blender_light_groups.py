"""Light groups through the add-on: the view layer's Light Groups become passes named as Cycles names them
("Combined_<name>", RGB), the lights', the emissive mesh's and the world's Light Group decide where their light goes,
and in an F12 render read back through Blender's EXR the groups add up to Combined (every emitter is in one); Cycles'
own render of the scene has the same pass names."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered, needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]


from .test_blender_light_passes import _addon  # noqa: E402, F401  (autouse: the engine's crashes fail the test)


def _scene():
    sc = scenes.new_scene(40, 28, engine="RESTIRCL")
    scenes.quad("Floor", 10.0, 10.0, scenes.diffuse_material("Floor", (0.8, 0.8, 0.8)))
    scenes.box("Box", (0.8, 0.8, 0.8), scenes.principled_material("Shiny", (0.8, 0.3, 0.2)), location=(0.3, 0, 0.4))
    key = scenes.light("AREA", "Key", (1.0, 0.0, 2.2), energy=80.0, shape="DISK", size=0.8)
    fill = scenes.light("POINT", "Fill", (-1.5, -1.0, 1.5), energy=60.0)
    lamp = scenes.quad("Lamp", 0.6, 0.3, scenes.emission_material("Glow", (1.0, 0.7, 0.4), 6.0),
                       location=(0, 1.0, 1.8), facing_down=True)
    scenes.camera((0.0, -5.0, 2.5), (0.0, 0.5, 0.6), lens=28.0)
    bg = sc.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.05, 0.07, 0.1, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    vl = sc.view_layers[0]
    for name in ("warm", "cool"):
        vl.lightgroups.add(name=name)
    key.lightgroup = lamp.lightgroup = "warm"
    fill.lightgroup = sc.world.lightgroup = "cool"
    sc.cycles.max_bounces = 1
    sc.restircl.method = "ris"
    sc.restircl.samples = 4
    return sc


def test_the_export_names_the_groups():
    ensure_registered()
    from restircl_blender.export.scene import export_scene

    _scene()
    ex = export_scene(bpy.context.evaluated_depsgraph_get())
    assert ex.scene.light_groups == ["warm", "cool"]
    assert {lt.name: lt.lightgroup for lt in ex.scene.lights} == {"Key": "warm", "Fill": "cool"}
    assert {m.name: m.lightgroup for m in ex.scene.meshes}["Lamp"] == "warm"
    assert ex.scene.environment is not None and ex.scene.environment.lightgroup == "cool"


def test_f12_writes_one_pass_per_group_that_adds_up_to_combined(tmp_path):
    sc = _scene()
    render_to(sc, tmp_path / "ours.exr")
    ours = read_exr_passes(tmp_path / "ours.exr")
    assert {"Combined_warm", "Combined_cool"} <= set(ours)
    # read_exr_passes orders the channels of a pass it does not know by name: B, G, R
    warm, cool = ours["Combined_warm"][..., ::-1], ours["Combined_cool"][..., ::-1]
    assert warm.shape[-1] == 3 and warm.mean() > 0.01 and cool.mean() > 0.01
    combined = ours["Combined"][..., :3]
    assert np.abs(warm + cool - combined).max() < 1e-4 * max(1.0, float(combined.max()))
    sc.render.engine = "CYCLES"
    sc.cycles.samples = 2
    render_to(sc, tmp_path / "cycles.exr")
    assert {"Combined_warm", "Combined_cool"} <= set(read_exr_passes(tmp_path / "cycles.exr"))


def test_no_groups_no_passes(tmp_path):
    sc = _scene()
    vl = sc.view_layers[0]
    while len(vl.lightgroups):
        vl.lightgroups.remove(vl.lightgroups[0])
    render_to(sc, tmp_path / "ours.exr")
    assert not any(name.startswith("Combined_") for name in read_exr_passes(tmp_path / "ours.exr"))
