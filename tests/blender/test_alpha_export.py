"""Export of transparency (issue 39) to Material.alpha: the Principled BSDF's Alpha (a constant, an Image Texture's
Alpha output), the Transparent BSDF alone and under a Mix Shader with another closure (a constant or an image
factor, the Transparent BSDF in either slot), and a Principled Alpha under such a Mix."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl import ImageTexture, Invert  # noqa: E402

from . import test_blender_materials as mt  # noqa: E402

pytestmark = pytest.mark.blender
_addon = mt._addon  # the add-on registered, as for every export test
add_node, exported, fresh_scene, node_material, principled = (mt.add_node, mt.exported, mt.fresh_scene,
                                                              mt.node_material, mt.principled)


def _image_node(tree):
    img = bpy.data.images.new("leaf", 4, 4, alpha=True)
    px = np.ones((4, 4, 4), np.float32)
    px[..., 3] = np.tile([0.0, 1.0], 8).reshape(4, 4)
    img.pixels.foreach_set(px.reshape(-1))
    return add_node(tree, "ShaderNodeTexImage", image=img)


def _with_uvs():
    for ob in bpy.context.scene.objects:
        if ob.type == "MESH" and not ob.data.uv_layers:
            ob.data.uv_layers.new(name="UVMap")


def _export(*mats):
    from restircl_blender import export as ex

    for k, m in enumerate(mats):
        mt.on_quad(m, 1.0 + k)
    _with_uvs()
    exp = ex.export_scene(bpy.context.evaluated_depsgraph_get())
    return {m.name: m for m in exp.scene.materials}, exp.warnings


def test_principled_alpha_constant_and_emission():
    fresh_scene()
    mat, _tree, _p = principled("Veil", **{"Alpha": 0.3, "Emission Strength": 2.0,
                                           "Emission Color": (1.0, 0.5, 0.25, 1.0)})
    mats, warnings = exported(mat)
    m = mats["Veil"]
    assert m.alpha == pytest.approx(0.3) and not mt.warnings_of(warnings, "Veil")
    # Cycles scales the emission by the Alpha; the renderer's coverage scales it again: stored whole
    assert m.emission_strength * max(m.emission) == pytest.approx(2.0)


def test_principled_alpha_from_an_image():
    fresh_scene()
    mat, tree, p = principled("Leaf")
    tex = _image_node(tree)
    tree.links.new(tex.outputs["Alpha"], p.inputs["Alpha"])
    m = _export(mat)[0]["Leaf"]
    assert isinstance(m.alpha, ImageTexture) and m.alpha.alpha
    assert m.alpha.image.shape[:2] == (4, 4)


def test_transparent_bsdf_alone_and_mixed():
    fresh_scene()
    clear, tree, out = node_material("Clear")
    t = add_node(tree, "ShaderNodeBsdfTransparent")
    tree.links.new(t.outputs[0], out.inputs["Surface"])
    mixed, tree, out = node_material("Mixed")
    t = add_node(tree, "ShaderNodeBsdfTransparent")
    d = add_node(tree, "ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.4, 0.6, 1.0)})
    mix = add_node(tree, "ShaderNodeMixShader", {"Fac": 0.25})
    tree.links.new(t.outputs[0], mix.inputs[1])
    tree.links.new(d.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(clear, mixed)
    assert mats["Clear"].alpha == 0.0
    m = mats["Mixed"]
    assert m.alpha == pytest.approx(0.25) and m.kind == "diffuse" and not m.layers
    assert m.albedo == pytest.approx((0.2, 0.4, 0.6))  # the closure at its full weight within the coverage
    assert not mt.warnings_of(warnings, "Mixed")


def test_mix_factor_from_an_image_in_either_slot():
    fresh_scene()
    mats = []
    for name, transparent_first in (("First", True), ("Second", False)):
        mat, tree, out = node_material(name)
        t = add_node(tree, "ShaderNodeBsdfTransparent")
        d = add_node(tree, "ShaderNodeBsdfDiffuse")
        mix = add_node(tree, "ShaderNodeMixShader")
        tree.links.new(_image_node(tree).outputs["Alpha"], mix.inputs["Fac"])
        a, b = (t, d) if transparent_first else (d, t)
        tree.links.new(a.outputs[0], mix.inputs[1])
        tree.links.new(b.outputs[0], mix.inputs[2])
        tree.links.new(mix.outputs[0], out.inputs["Surface"])
        mats.append(mat)
    got = _export(*mats)[0]
    assert isinstance(got["First"].alpha, ImageTexture)  # the diffuse takes the factor's share
    assert isinstance(got["Second"].alpha, Invert) and isinstance(got["Second"].alpha.color, ImageTexture)
    assert got["First"].kind == "diffuse" and not got["First"].layers


def test_principled_alpha_under_a_transparent_mix_multiplies():
    fresh_scene()
    mat, tree, p = principled("Both", Alpha=0.5)
    out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    t = add_node(tree, "ShaderNodeBsdfTransparent")
    mix = add_node(tree, "ShaderNodeMixShader", {"Fac": 0.6})
    tree.links.new(t.outputs[0], mix.inputs[1])
    tree.links.new(p.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    assert exported(mat)[0]["Both"].alpha == pytest.approx(0.3)


def test_coloured_transparent_is_grey_with_a_warning():
    fresh_scene()
    mat, tree, out = node_material("Tint")
    t = add_node(tree, "ShaderNodeBsdfTransparent", {"Color": (1.0, 0.4, 0.4, 1.0)})
    tree.links.new(t.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(mat)
    assert mats["Tint"].alpha == pytest.approx(0.4)
    assert any("grey" in w for w in mt.warnings_of(warnings, "Tint"))
