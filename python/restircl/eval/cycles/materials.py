"""restircl Materials as Blender shader nodes, for the Cycles bridge (eval/cycles/bridge.py): the Principled BSDF,
Diffuse, Glossy, Glass and Refraction BSDFs with constant inputs, two of them under a Mix Shader or Add Shader, and
the material's emission. Texture inputs are not written (the bridge renders constant materials)."""

from __future__ import annotations

from ...materials.closures.registry import kind_of
from ...materials.material import Material
from ...materials.textures import is_texture

_DISTRIBUTION = {"multi_ggx": "MULTI_GGX", "ggx": "GGX"}


def _rgba(v) -> tuple[float, float, float, float]:
    r, g, b = (float(x) for x in v)
    return (r, g, b, 1.0)


def _diffuse(tree, c: Material):
    n = tree.nodes.new("ShaderNodeBsdfDiffuse")
    n.inputs["Color"].default_value = _rgba(c.albedo)
    n.inputs["Roughness"].default_value = 0.0
    return n


def _glossy(tree, c: Material):
    n = tree.nodes.new("ShaderNodeBsdfGlossy")
    n.distribution = _DISTRIBUTION[c.distribution]
    n.inputs["Color"].default_value = _rgba(c.albedo)
    n.inputs["Roughness"].default_value = float(c.roughness)
    return n


def _principled(tree, c: Material):
    n = tree.nodes.new("ShaderNodeBsdfPrincipled")
    n.distribution = _DISTRIBUTION[c.distribution]
    n.inputs["Base Color"].default_value = _rgba(c.albedo)
    n.inputs["Metallic"].default_value = float(c.metallic)
    n.inputs["Roughness"].default_value = float(c.roughness)
    n.inputs["IOR"].default_value = float(c.ior)
    n.inputs["Specular IOR Level"].default_value = float(c.specular)
    n.inputs["Specular Tint"].default_value = _rgba(c.specular_tint)
    n.inputs["Transmission Weight"].default_value = float(c.transmission)
    if c.thin_wall:  # Blender 5.3's Principled only: an older Blender cannot build this material
        if "Thin Wall" not in n.inputs:
            raise ValueError(f"{c.name}: this Blender's Principled BSDF has no Thin Wall input")
        n.inputs["Thin Wall"].default_value = True
    _thin_film(n, c)
    return n


def _thin_film(n, c: Material) -> None:
    """The closure's Thin Film, where it has one (the node's inputs keep their defaults otherwise)."""
    if float(c.thin_film_thickness) > 0:
        n.inputs["Thin Film Thickness"].default_value = float(c.thin_film_thickness)
        n.inputs["Thin Film IOR"].default_value = float(c.thin_film_ior)


def _dielectric(node_type: str):
    def write(tree, c: Material):
        n = tree.nodes.new(node_type)
        n.distribution = _DISTRIBUTION[c.distribution]
        n.inputs["Color"].default_value = _rgba(c.albedo)
        n.inputs["Roughness"].default_value = float(c.roughness)
        n.inputs["IOR"].default_value = float(c.ior)
        if "thin_film_thickness" in kind_of(c.kind).fields:
            _thin_film(n, c)
        return n
    return write


# Material.kind (restircl.materials.closures) -> the writer of its shader node
NODE_WRITERS = {"principled": _principled, "diffuse": _diffuse, "glossy": _glossy,
                "glass": _dielectric("ShaderNodeBsdfGlass"), "refraction": _dielectric("ShaderNodeBsdfRefraction")}


def _closure(tree, c: Material):
    """One shader node for closure c (a Material without layers)."""
    kind = kind_of(c.kind)
    for name in kind.fields:
        if name != "normal" and is_texture(getattr(c, name)):  # normal maps are not written
            raise ValueError(f"material {c.name!r}: the Cycles bridge writes constant inputs only ({name})")
    if kind.name not in NODE_WRITERS:
        raise ValueError(f"material {c.name!r}: the Cycles bridge has no shader node for kind {kind.name!r}")
    return NODE_WRITERS[kind.name](tree, c)


def _combine(tree, a, b, mix: float | None):
    node = tree.nodes.new("ShaderNodeAddShader" if mix is None else "ShaderNodeMixShader")
    first = 0 if mix is None else 1
    if mix is not None:
        node.inputs["Fac"].default_value = float(mix)
    tree.links.new(a.outputs[0], node.inputs[first])
    tree.links.new(b.outputs[0], node.inputs[first + 1])
    return node


def material_to_bpy(bpy, mat: Material, node_material):
    """A bpy material for `mat`; node_material(bpy, name) -> (material, tree, output node) makes the empty one."""
    m, tree, out = node_material(bpy, mat.name)
    if mat.layers:
        if mat.mix is not None and is_texture(mat.mix):
            raise ValueError(f"material {mat.name!r}: the Cycles bridge writes a constant Mix factor only")
        a, b = (_closure(tree, c) for c in mat.layers)
        shader = _combine(tree, a, b, None if mat.mix is None else float(mat.mix))
    else:
        shader = _closure(tree, mat)
    if mat.is_emissive:
        e = tree.nodes.new("ShaderNodeEmission")
        e.inputs["Color"].default_value = _rgba(mat.emission)
        e.inputs["Strength"].default_value = float(mat.emission_strength)
        shader = _combine(tree, shader, e, None)
    tree.links.new(shader.outputs[0], out.inputs["Surface"])
    return m


def is_plain_diffuse(mat: Material) -> bool:
    """A material the bridge has always written (a Diffuse BSDF of the albedo): no specular lobe, one closure."""
    if mat.layers:
        return False
    if mat.kind == "diffuse":
        return True
    if mat.kind != "principled" or float(mat.transmission) > 0:
        return False
    return not is_texture(mat.metallic) and not is_texture(mat.specular) and float(mat.metallic) == 0.0 \
        and float(mat.specular) == 0.0
