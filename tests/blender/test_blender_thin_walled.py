"""Thin-walled glass and thin film (issue 39), as Blender's Cycles has them: up to Blender 5.0 no shader node has a
thin-walled mode (no "Thin Wall" input or property on any BSDF node: Cycles models a pane as the two surfaces of a
solid, or one sheet that refracts in and never out); Blender 5.3's Principled BSDF has a Thin Wall input (no other
node has one), which the add-on exports as the material's `thin_wall` (opencl/bsdf/closures/thin_wall.h; its
agreement with Cycles: test_blender_cycles_thin_wall.py), without a warning. Meanwhile the Glass, the Principled and
the Metallic BSDF have Thin Film (Thickness, IOR), an iridescent coating that changes their Fresnel, for glass both
what it reflects and what it transmits: the add-on exports it (Material.thin_film_thickness, thin_film_ior; rendered
by opencl/bsdf/thin_film.h, against Cycles in test_blender_thin_film_cycles.py) without a warning; a film of
thickness 0 (the default) is no film."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402
from restircl.eval.cycles.bridge import node_material  # noqa: E402

from .test_blender_support import ensure_registered  # noqa: E402

pytestmark = pytest.mark.blender
FILMED = ("ShaderNodeBsdfGlass", "ShaderNodeBsdfPrincipled", "ShaderNodeBsdfMetallic")


def _bsdf_node_types() -> list[str]:
    return sorted(n for n in dir(bpy.types) if n.startswith("ShaderNodeBsdf") or n == "ShaderNodeSubsurfaceScattering")


def _has_thin_wall(node) -> bool:
    names = [s.name.lower() for s in node.inputs] + [p.identifier.lower() for p in node.bl_rna.properties]
    return any("thin" in n and "wall" in n for n in names)


def principled_has_thin_wall() -> bool:
    """Whether this Blender's Principled BSDF has a Thin Wall input (Blender 5.3)"""
    _, tree, _ = node_material(bpy, "probe")
    return _has_thin_wall(tree.nodes.new("ShaderNodeBsdfPrincipled"))


def test_only_the_principled_bsdf_may_have_a_thin_wall():
    _, tree, _ = node_material(bpy, "probe")
    seen = []
    for kind in _bsdf_node_types():
        node = tree.nodes.new(kind)
        assert kind == "ShaderNodeBsdfPrincipled" or not _has_thin_wall(node), kind
        if any(s.name == "Thin Film Thickness" for s in node.inputs):
            seen.append(kind)
    assert len(_bsdf_node_types()) >= 10
    assert all(k in seen for k in FILMED if hasattr(bpy.types, k)), seen


def _glass(name: str, thickness: float):
    mat, tree, out = node_material(bpy, name)
    g = tree.nodes.new("ShaderNodeBsdfGlass")
    g.inputs["Roughness"].default_value = 0.2
    g.inputs["Thin Film Thickness"].default_value = thickness
    tree.links.new(g.outputs[0], out.inputs["Surface"])
    return mat


def _export_two_quads(material, with_it: str, without_it: str):
    """The add-on's export of two quads under a lamp, of materials material(name, True) and material(name, False)
    (made after the new scene, which removes the materials before it)."""
    ensure_registered()
    from restircl_blender import export as ex

    scenes.new_scene(32, 24)
    scenes.quad(with_it, 1, material=material(with_it, True), location=(0, 0, 1))
    scenes.quad(without_it, 1, material=material(without_it, False), location=(0, 0, 2))
    scenes.light("POINT", "Lamp", (0, 0, 5), energy=100.0)
    scenes.camera((0, -6, 4), (0, 0, 1))
    return ex.export_scene(bpy.context.evaluated_depsgraph_get(), None, frame_set=bpy.context.scene.frame_set)


def test_glass_with_a_thin_film_exports_its_film_without_a_warning():
    exp = _export_two_quads(lambda name, on: _glass(name, 400.0 if on else 0.0), "Filmed", "Clear")
    mats = {m.name: m for m in exp.scene.materials}
    assert mats["Filmed"].kind == mats["Clear"].kind == "glass"
    assert mats["Filmed"].thin_film_thickness == pytest.approx(400.0)
    assert mats["Filmed"].thin_film_ior == pytest.approx(1.33)
    assert mats["Clear"].thin_film_thickness == 0.0
    assert not any("thin film" in w for w in exp.warnings), exp.warnings


def test_principled_and_metallic_films_are_exported():
    def filmed(kind: str):
        def make(name: str, on: bool):
            mat, tree, out = node_material(bpy, name)
            n = tree.nodes.new(kind)
            n.inputs["Thin Film Thickness"].default_value = 250.0 if on else 0.0
            n.inputs["Thin Film IOR"].default_value = 1.6
            tree.links.new(n.outputs[0], out.inputs["Surface"])
            return mat
        return make

    for kind in ("ShaderNodeBsdfPrincipled", "ShaderNodeBsdfMetallic"):
        if not hasattr(bpy.types, kind):
            continue
        exp = _export_two_quads(filmed(kind), "Filmed", "Clear")
        mats = {m.name: m for m in exp.scene.materials}
        assert mats["Filmed"].thin_film_thickness == pytest.approx(250.0), kind
        assert mats["Filmed"].thin_film_ior == pytest.approx(1.6), kind
        assert mats["Clear"].thin_film_thickness == 0.0, kind
        assert not any("thin film" in w for w in exp.warnings), (kind, exp.warnings)


def _thin_walled(name: str, thin: bool, linked: bool = False):
    """A Principled BSDF of Transmission 1 with Thin Wall `thin`, linked to a Value node where `linked`"""
    mat, tree, out = node_material(bpy, name)
    p = tree.nodes.new("ShaderNodeBsdfPrincipled")
    p.inputs["Transmission Weight"].default_value = 1.0
    p.inputs["Thin Wall"].default_value = thin
    if linked:
        tree.links.new(tree.nodes.new("ShaderNodeValue").outputs[0], p.inputs["Thin Wall"])
    tree.links.new(p.outputs[0], out.inputs["Surface"])
    return mat


def test_principled_thin_wall_exports_as_a_thin_wall_without_a_warning():
    ensure_registered()
    if not principled_has_thin_wall():
        pytest.skip("this Blender's Principled BSDF has no Thin Wall input")

    exp = _export_two_quads(_thin_walled, "Walled", "Solid")
    mats = {m.name: m for m in exp.scene.materials}
    assert mats["Walled"].thin_wall is True and mats["Solid"].thin_wall is False
    assert mats["Walled"].transmission == mats["Solid"].transmission == 1.0
    assert not any("Walled" in w or "Solid" in w for w in exp.warnings), exp.warnings


def test_a_linked_thin_wall_is_taken_as_its_default_with_a_warning():
    ensure_registered()
    if not principled_has_thin_wall():
        pytest.skip("this Blender's Principled BSDF has no Thin Wall input")

    exp = _export_two_quads(lambda name, on: _thin_walled(name, True, linked=on), "Driven", "Fixed")
    mats = {m.name: m for m in exp.scene.materials}
    assert mats["Driven"].thin_wall is True and mats["Fixed"].thin_wall is True
    assert any("Driven" in w and "linked Thin Wall" in w for w in exp.warnings), exp.warnings
    assert not any("Fixed" in w for w in exp.warnings), exp.warnings


def test_a_filmed_part_metal_with_transmission_says_its_glass_is_left_out():
    """A film makes the metal and the specular each a lobe; with Transmission Weight too the glass lobe is past what
    a material holds (MAX_LAYERS): the warning names it (the same without the film: no warning)."""
    def principled(name: str, on: bool):
        mat, tree, out = node_material(bpy, name)
        p = tree.nodes.new("ShaderNodeBsdfPrincipled")
        p.inputs["Metallic"].default_value = 0.5
        p.inputs["Transmission Weight"].default_value = 1.0
        p.inputs["Thin Film Thickness"].default_value = 300.0 if on else 0.0
        tree.links.new(p.outputs[0], out.inputs["Surface"])
        return mat

    exp = _export_two_quads(principled, "Filmed", "Clear")
    assert any("Filmed" in w and "transmission is left out" in w for w in exp.warnings), exp.warnings
    assert not any("Clear" in w for w in exp.warnings), exp.warnings


def test_a_thin_film_on_a_thin_wall_is_left_out_with_a_warning():
    """The filmed Principled resolve has no sheet: the add-on keeps the Thin Wall and names the film it leaves out."""
    ensure_registered()
    if not principled_has_thin_wall():
        pytest.skip("this Blender's Principled BSDF has no Thin Wall input")

    def walled(name: str, on: bool):
        mat = _thin_walled(name, True)
        p = next(n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
        p.inputs["Thin Film Thickness"].default_value = 300.0 if on else 0.0
        return mat

    exp = _export_two_quads(walled, "Filmed", "Clear")
    mats = {m.name: m for m in exp.scene.materials}
    assert mats["Filmed"].thin_wall is True and mats["Filmed"].thin_film_thickness == 0.0
    assert any("Filmed" in w and "thin film on a Thin Wall" in w for w in exp.warnings), exp.warnings
    assert not any("Clear" in w for w in exp.warnings), exp.warnings
