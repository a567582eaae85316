"""Export of Blender shader graphs to restircl.Material: each shader node, Mix and Add Shaders, groups, and what
is left out (one warning per material, never an exception)."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def export(**kw):
    """The export of the current scene; every material it gives passes the renderer's own check."""
    from restircl.materials.check import check_material
    from restircl_blender import export as ex

    exp = ex.export_scene(bpy.context.evaluated_depsgraph_get(), **kw)
    for m in exp.scene.materials:
        check_material(m)
    return exp


def node_material(name: str):
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None:  # Blender before 5.0 makes a new material without a node tree
        mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    return mat, tree, tree.nodes.new("ShaderNodeOutputMaterial")


def socket(sockets, identifier: str):
    return next(s for s in sockets if s.identifier == identifier)


def add_node(tree, kind: str, inputs: dict | None = None, **props):
    """A node of `kind` with the given input values (by name) and properties."""
    node = tree.nodes.new(kind)
    for name, value in (inputs or {}).items():
        node.inputs[name].default_value = value
    for name, value in props.items():
        setattr(node, name, value)
    return node


def on_quad(mat, z: float = 1.0):
    scenes.quad(mat.name, 1.0, material=mat, location=(0, 0, z))


def fresh_scene():
    sc = scenes.new_scene(32, 24)
    scenes.light("SUN", "Sun", (0, 0, 5), energy=2.0)
    scenes.camera((0, -6, 4), (0, 0, 0))
    return sc


def exported(*materials) -> tuple[dict, list[str]]:
    for k, m in enumerate(materials):
        on_quad(m, 1.0 + k)
    exp = export()
    return {m.name: m for m in exp.scene.materials}, exp.warnings


def warnings_of(warnings: list[str], name: str) -> list[str]:
    return [w for w in warnings if f"material {name!r}" in w]


principled = scenes.principled_nodes


def test_principled_fields():
    fresh_scene()
    mat, _tree, p = principled("Metal", **{"Base Color": (0.9, 0.6, 0.2, 1.0), "Metallic": 1.0, "Roughness": 0.3,
                                           "IOR": 1.45, "Specular IOR Level": 0.7,
                                           "Specular Tint": (1.0, 0.9, 0.8, 1.0)})
    p.distribution = "GGX"
    mats, warnings = exported(mat)
    m = mats["Metal"]
    assert m.kind == "principled" and not m.layers
    assert m.albedo == pytest.approx((0.9, 0.6, 0.2))
    assert (m.metallic, m.roughness, m.ior, m.specular) == pytest.approx((1.0, 0.3, 1.45, 0.7))
    assert m.specular_tint == pytest.approx((1.0, 0.9, 0.8))
    assert m.distribution == "ggx" and m.normal is None
    assert not warnings_of(warnings, "Metal")


def test_principled_defaults_keep_blender_specular():
    """Blender's Principled default Specular IOR Level is 0.5 (the IOR's own reflectance): exported as it is."""
    fresh_scene()
    mat, _tree, _p = principled("Plastic")
    m = exported(mat)[0]["Plastic"]
    assert m.specular == pytest.approx(0.5) and m.distribution == "multi_ggx" and m.ior == pytest.approx(1.5)


def test_unsupported_lobes_are_named_in_one_warning():
    fresh_scene()
    mat, _tree, _p = principled("Fancy", **{"Coat Weight": 0.5, "Sheen Weight": 0.2, "Transmission Weight": 1.0,
                                            "Alpha": 0.5, "Subsurface Weight": 0.0})
    mats, warnings = exported(mat)
    mine = [w for w in warnings_of(warnings, "Fancy") if "coat" in w]
    assert len(mine) == 1, mine
    for lobe in ("coat", "sheen"):
        assert lobe in mine[0]
    assert "subsurface" not in mine[0] and "transmission" not in mine[0]
    assert "alpha" not in mine[0]  # Alpha is the coverage (test_alpha_export.py)
    assert mats["Fancy"].transmission == pytest.approx(1.0)  # rendered: glass (opencl/bsdf/closures/glass.h)


def test_diffuse_glossy_and_metallic_nodes():
    fresh_scene()
    dmat, tree, out = node_material("Dif")
    d = add_node(tree, "ShaderNodeBsdfDiffuse", {"Color": (0.1, 0.2, 0.3, 1), "Roughness": 0.0})
    tree.links.new(d.outputs[0], out.inputs["Surface"])
    gmat, tree, out = node_material("Glo")
    g = add_node(tree, "ShaderNodeBsdfGlossy", {"Color": (0.5, 0.6, 0.7, 1), "Roughness": 0.05},
                 distribution="BECKMANN")
    tree.links.new(g.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(dmat, gmat)
    assert mats["Dif"].kind == "diffuse" and mats["Dif"].albedo == pytest.approx((0.1, 0.2, 0.3))
    assert mats["Glo"].kind == "glossy" and mats["Glo"].roughness == pytest.approx(0.05)
    assert mats["Glo"].distribution == "ggx"
    assert any("BECKMANN" in w for w in warnings_of(warnings, "Glo"))
    assert not warnings_of(warnings, "Dif")
    if hasattr(bpy.types, "ShaderNodeBsdfMetallic"):
        mmat, tree, out = node_material("Met")
        n = add_node(tree, "ShaderNodeBsdfMetallic", {"Base Color": (0.9, 0.8, 0.7, 1), "Edge Tint": (0.5, 0.5, 1, 1)})
        tree.links.new(n.outputs[0], out.inputs["Surface"])
        m = exported(mmat)[0]["Met"]
        assert m.kind == "principled" and m.metallic == 1.0 and m.specular_tint == pytest.approx((0.5, 0.5, 1.0))


def _two_bsdfs(name: str, shader: str, fac: float | None = None):
    mat, tree, out = node_material(name)
    d = tree.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (1, 0, 0, 1)
    d.inputs["Roughness"].default_value = 0.0
    p = tree.nodes.new("ShaderNodeBsdfPrincipled")
    m = tree.nodes.new(shader)
    if fac is not None:
        m.inputs["Fac"].default_value = fac
    shaders = [s for s in m.inputs if s.type == "SHADER"]
    tree.links.new(d.outputs[0], shaders[0])
    tree.links.new(p.outputs[0], shaders[1])
    tree.links.new(m.outputs[0], out.inputs["Surface"])
    return mat, tree, m


def test_mix_and_add_shaders_become_layers():
    fresh_scene()
    mix, _t, _m = _two_bsdfs("MixS", "ShaderNodeMixShader", 0.3)
    add, _t, _m = _two_bsdfs("AddS", "ShaderNodeAddShader")
    mats, warnings = exported(mix, add)
    m = mats["MixS"]
    assert [c.kind for c in m.layers] == ["diffuse", "principled"] and m.mix == pytest.approx(0.3)
    a = mats["AddS"]
    assert [c.kind for c in a.layers] == ["diffuse", "principled"] and a.mix is None
    assert not warnings_of(warnings, "MixS") and not warnings_of(warnings, "AddS")


def test_mix_shader_with_a_texture_factor():
    fresh_scene()
    mat, tree, m = _two_bsdfs("TexMix", "ShaderNodeMixShader")
    chk = tree.nodes.new("ShaderNodeTexChecker")
    tree.links.new(chk.outputs["Fac"], m.inputs["Fac"])
    t = exported(mat)[0]["TexMix"]
    assert isinstance(t.mix, restircl.materials.textures.CheckerTexture)
    assert t.mix.color1 == (1.0, 1.0, 1.0) and t.mix.color2 == (0.0, 0.0, 0.0)


def test_too_many_closures_warn_naming_what_is_dropped():
    fresh_scene()
    mat, tree, out = node_material("Three")
    a, b, c = (tree.nodes.new("ShaderNodeBsdfDiffuse") for _ in range(3))
    c.name = "Faint"
    add1, mix = tree.nodes.new("ShaderNodeAddShader"), tree.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.1
    tree.links.new(a.outputs[0], add1.inputs[0])
    tree.links.new(b.outputs[0], mix.inputs[1])
    tree.links.new(c.outputs[0], mix.inputs[2])
    tree.links.new(mix.outputs[0], add1.inputs[1])
    tree.links.new(add1.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(mat)
    assert len(mats["Three"].layers) == 2
    assert any("left out" in w and "Faint" in w for w in warnings_of(warnings, "Three"))


def test_emission_mixed_with_a_bsdf():
    fresh_scene()
    mat, tree, out = node_material("Glow")
    p = tree.nodes.new("ShaderNodeBsdfPrincipled")
    e = add_node(tree, "ShaderNodeEmission", {"Color": (1.0, 0.5, 0.0, 1.0), "Strength": 10.0})
    m = add_node(tree, "ShaderNodeMixShader", {"Fac": 0.2})
    for a, b in ((p.outputs[0], m.inputs[1]), (e.outputs[0], m.inputs[2]), (m.outputs[0], out.inputs["Surface"])):
        tree.links.new(a, b)
    g = exported(mat)[0]["Glow"]
    assert g.radiance == pytest.approx((2.0, 1.0, 0.0))
    # the Principled keeps weight 0.8: mixed with a black closure
    assert [c.kind for c in g.layers] == ["principled", "diffuse"] and g.mix == pytest.approx(0.2)
    assert g.layers[1].albedo == (0.0, 0.0, 0.0)


def test_reroutes_and_simple_groups_pass_through():
    fresh_scene()
    group = bpy.data.node_groups.new("Shiny", "ShaderNodeTree")
    group.interface.new_socket("Tint", in_out="INPUT", socket_type="NodeSocketColor")
    group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    gin, gout = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    glossy = group.nodes.new("ShaderNodeBsdfGlossy")
    group.links.new(gin.outputs[0], glossy.inputs["Color"])
    group.links.new(glossy.outputs[0], gout.inputs[0])
    mat, tree, out = node_material("Grouped")
    node = tree.nodes.new("ShaderNodeGroup")
    node.node_tree = group
    node.inputs[0].default_value = (0.2, 0.9, 0.4, 1.0)
    reroute = tree.nodes.new("NodeReroute")
    tree.links.new(node.outputs[0], reroute.inputs[0])
    tree.links.new(reroute.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(mat)
    assert mats["Grouped"].kind == "glossy" and mats["Grouped"].albedo == pytest.approx((0.2, 0.9, 0.4))
    assert not warnings_of(warnings, "Grouped")


def test_node_loop_is_one_warning_not_an_exception():
    fresh_scene()
    mat, tree, out = node_material("Loop")
    p = tree.nodes.new("ShaderNodeBsdfPrincipled")
    m1, m2 = tree.nodes.new("ShaderNodeMix"), tree.nodes.new("ShaderNodeMix")
    m1.data_type = m2.data_type = "RGBA"
    tree.links.new(socket(m1.outputs, "Result_Color"), socket(m2.inputs, "A_Color"))
    tree.links.new(socket(m2.outputs, "Result_Color"), socket(m1.inputs, "A_Color"))
    tree.links.new(socket(m2.outputs, "Result_Color"), p.inputs["Base Color"])
    tree.links.new(p.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(mat)
    mine = warnings_of(warnings, "Loop")
    assert len(mine) == 1 and "loop" in mine[0], mine
    # the link that closes the loop reads as the input's own value: a finite graph of Mix nodes
    albedo = mats["Loop"].albedo
    while isinstance(albedo, restircl.materials.textures.MixColor):
        albedo = albedo.a
    assert albedo == pytest.approx(tuple(socket(m1.inputs, "A_Color").default_value[:3]))


def test_unsupported_shader_node_is_named():
    fresh_scene()
    mat, tree, out = node_material("Hairy")
    g = tree.nodes.new("ShaderNodeBsdfHair")
    tree.links.new(g.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(mat)
    mine = warnings_of(warnings, "Hairy")
    assert len(mine) == 1 and "Hair BSDF" in mine[0] and "left out" in mine[0]
    assert mats["Hairy"].albedo == (0.0, 0.0, 0.0)


def test_glass_and_refraction_nodes_are_exported():
    """The Glass and Refraction BSDFs become closures of their kinds with Color, Roughness, IOR and distribution;
    GGX without a warning, Multiscatter GGX with one (the glass lobes scatter once)."""
    fresh_scene()
    gmat, tree, out = node_material("Glassy")
    g = add_node(tree, "ShaderNodeBsdfGlass", {"Color": (0.9, 0.8, 0.7, 1), "Roughness": 0.2, "IOR": 1.33},
                 distribution="GGX")
    tree.links.new(g.outputs[0], out.inputs["Surface"])
    rmat, tree, out = node_material("Bent")
    r = add_node(tree, "ShaderNodeBsdfRefraction", {"Color": (0.5, 0.5, 0.5, 1), "Roughness": 0.0, "IOR": 1.6})
    tree.links.new(r.outputs[0], out.inputs["Surface"])
    mats, warnings = exported(gmat, rmat)
    glass = mats["Glassy"]
    assert glass.kind == "glass" and glass.albedo == pytest.approx((0.9, 0.8, 0.7))
    assert glass.roughness == pytest.approx(0.2) and glass.ior == pytest.approx(1.33) and glass.distribution == "ggx"
    assert warnings_of(warnings, "Glassy") == []
    bent = mats["Bent"]
    assert bent.kind == "refraction" and bent.ior == pytest.approx(1.6) and bent.roughness == pytest.approx(0.0)
    assert all("left out" not in w for w in warnings_of(warnings, "Bent"))


def test_out_of_range_inputs_are_clamped_as_cycles_does():
    fresh_scene()
    mat, tree, p = principled("Wild", **{"IOR": 0.0})
    v = add_node(tree, "ShaderNodeValue")
    v.outputs[0].default_value = -0.5
    tree.links.new(v.outputs[0], p.inputs["Roughness"])
    rgb = add_node(tree, "ShaderNodeRGB")
    rgb.outputs[0].default_value = (-1.0, 0.5, 2.0, 1.0)
    fmix = add_node(tree, "ShaderNodeMix", data_type="FLOAT")
    tree.links.new(v.outputs[0], socket(fmix.inputs, "B_Float"))
    tree.links.new(socket(fmix.outputs, "Result_Float"), p.inputs["Metallic"])
    tree.links.new(rgb.outputs[0], p.inputs["Base Color"])
    mats, warnings = exported(mat)
    m = mats["Wild"]
    assert m.roughness == 0.0 and m.albedo == (0.0, 0.5, 2.0) and m.ior == 1.0
    assert isinstance(m.metallic, restircl.materials.textures.MixColor) and m.metallic.b == (0.0, 0.0, 0.0)
    mine = warnings_of(warnings, "Wild")
    assert any("Roughness -0.5" in w for w in mine) and any("IOR" in w for w in mine)
