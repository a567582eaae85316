"""Color Attribute and Attribute nodes (issue 41) read natively: the export gives each mesh the colour attributes its
materials read, per triangle corner (add-on export/mesh.py), and a restircl Attribute node (export/inputs.py); the
device blends the corners by barycentrics (opencl/textures/nodes.h). A grid whose default colour attribute (point
domain, float) and a second one (corner domain, bytes) are mixed into Base Color, under a sun, against Cycles. Negative
control: the same render without the attributes (what a missing attribute reads, 0) fails the bound."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import needs_renderer  # noqa: E402

pytestmark = pytest.mark.blender


def _scene():
    sc = scenes.new_scene(48, 36)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=5, y_subdivisions=4, size=3.0)
    ob = bpy.context.object
    me = ob.data
    rng = np.random.default_rng(3)
    point = me.color_attributes.new("Col", "FLOAT_COLOR", "POINT")
    point.data.foreach_set("color", np.concatenate([rng.uniform(0.0, 1.0, (len(me.vertices), 3)),
                                                    np.ones((len(me.vertices), 1))], 1).reshape(-1))
    corner = me.color_attributes.new("Paint", "BYTE_COLOR", "CORNER")
    corner.data.foreach_set("color", np.concatenate([rng.uniform(0.0, 1.0, (len(me.loops), 3)),
                                                     np.ones((len(me.loops), 1))], 1).reshape(-1))
    me.color_attributes.active_color = point
    me.color_attributes.render_color_index = me.color_attributes.find("Col")
    mat, tree, out = scenes.node_material(bpy, "Painted")
    p = tree.nodes.new("ShaderNodeBsdfDiffuse")
    vc = tree.nodes.new("ShaderNodeVertexColor")  # no name: the default colour attribute
    at = tree.nodes.new("ShaderNodeAttribute")
    at.attribute_name = "Paint"
    mix = tree.nodes.new("ShaderNodeMix")
    mix.data_type = "RGBA"
    mix.inputs["Factor"].default_value = 0.5
    tree.links.new(vc.outputs["Color"], mix.inputs["A"])
    tree.links.new(at.outputs["Color"], mix.inputs["B"])
    tree.links.new(mix.outputs["Result"], p.inputs["Color"])
    tree.links.new(p.outputs[0], out.inputs["Surface"])
    me.materials.append(mat)
    scenes.light("SUN", "Sun", (0, 0, 5), (math.radians(20), 0, 0), energy=3.0)
    scenes.camera((0.0, -0.5, 4.0), (0.0, 0.0, 0.0), lens=30.0)
    return sc, ob


def test_colour_attributes_are_exported_and_read_natively():
    from restircl import Attribute, MixColor

    from .test_blender_materials import export
    from .test_blender_support import ensure_registered

    ensure_registered()
    _sc, ob = _scene()
    exp = export(bake_resolution=16)
    m = next(m for m in exp.scene.materials if m.name == "Painted")
    assert isinstance(m.albedo, MixColor)
    assert (m.albedo.a, m.albedo.b) == (Attribute("", "color"), Attribute("Paint", "color"))
    assert not any("baked" in w for w in exp.warnings), exp.warnings
    (mesh,) = [x for x in exp.scene.meshes if x.name == ob.name]
    assert sorted(mesh.attributes) == ["", "Paint"]
    me = ob.data
    loops = np.empty(len(me.loop_triangles) * 3, np.int64)
    me.loop_triangles.foreach_get("loops", loops)
    vert = np.array([me.loops[i].vertex_index for i in loops])
    want = np.array([tuple(me.color_attributes["Col"].data[v].color) for v in vert]).reshape(-1, 3, 4)
    np.testing.assert_allclose(mesh.attributes[""], want, atol=1e-6)
    paint = np.array([tuple(me.color_attributes["Paint"].data[i].color) for i in loops]).reshape(-1, 3, 4)
    np.testing.assert_allclose(mesh.attributes["Paint"], paint, atol=1e-6)


@needs_renderer
def test_colour_attributes_agree_with_cycles(tmp_path, record_property, monkeypatch):
    from restircl_blender import engine
    from restircl_blender.export import mesh as mesh_export

    from .test_blender_support import cycles_and_ours, read_exr_passes, relmse, render_to

    sc, _ob = _scene()
    err, ratio = cycles_and_ours(tmp_path, sc, 256, 64, "colour attributes")
    record_property("relmse", err)
    assert err < 1e-2 and ratio == pytest.approx(1.0, abs=0.02)
    cyc = read_exr_passes(tmp_path / "cycles.exr")["Combined"]
    monkeypatch.setattr(mesh_export, "_corner_colors", lambda me, loops: None)
    engine._SESSIONS.clear()
    render_to(sc, tmp_path / "none.exr")
    wrong = relmse(read_exr_passes(tmp_path / "none.exr")["Combined"], cyc)
    print(f"colour attributes left out: relMSE {100 * wrong:.3f} %")
    assert wrong > max(1e-2, 10 * err)
