"""Thin-walled glass and thin film (issue 39), as Blender's Cycles has them: no shader node has a thin-walled mode
(no "Thin Walled" input or property on any BSDF node: Cycles models a pane as the two surfaces of a solid, or one
sheet that refracts in and never out), while the Glass, the Principled and the Metallic BSDF have Thin Film
(Thickness, IOR), an iridescent coating that changes their Fresnel, for glass both what it reflects and what it
transmits. restircl does not model the film: the add-on exports such glass as glass without it and names the film in
the material's warning; a film of thickness 0 (the default) is no film and no warning."""

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


def test_no_bsdf_node_has_a_thin_walled_mode():
    _, tree, _ = node_material(bpy, "probe")
    seen = []
    for kind in _bsdf_node_types():
        node = tree.nodes.new(kind)
        names = [s.name.lower() for s in node.inputs] + [p.identifier.lower() for p in node.bl_rna.properties]
        assert not any("thin" in n and "wall" in n for n in names), (kind, names)
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


def test_glass_with_a_thin_film_exports_as_glass_with_a_warning():
    ensure_registered()
    from restircl_blender import export as ex

    scenes.new_scene(32, 24)
    scenes.quad("Filmed", 1, material=_glass("Filmed", 400.0), location=(0, 0, 1))
    scenes.quad("Clear", 1, material=_glass("Clear", 0.0), location=(0, 0, 2))
    scenes.light("POINT", "Lamp", (0, 0, 5), energy=100.0)
    scenes.camera((0, -6, 4), (0, 0, 1))
    exp = ex.export_scene(bpy.context.evaluated_depsgraph_get(), None, frame_set=bpy.context.scene.frame_set)
    mats = {m.name: m for m in exp.scene.materials}
    assert mats["Filmed"].kind == mats["Clear"].kind == "glass"
    assert any("Filmed" in w and "thin film" in w for w in exp.warnings), exp.warnings
    assert not any("Clear" in w for w in exp.warnings), exp.warnings
