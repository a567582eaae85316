"""The corpus of real assets (restircl.eval.assets) as the tests and tools/asset_corpus.py use it: each asset through
Blender's own glTF importer, scaled to the DamagedHelmet's size and set on the helmet's stage (gltf_scenes.py
helmet_stage), and the node coverage of its materials: every node type of each material, read natively, baked or
ignored by the export, as the export itself says (its bake warning names the node types baked; a node that feeds
nothing Cycles renders is ignored by both renderers)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import bpy
from mathutils import Matrix, Vector

from .gltf_scenes import helmet_stage, import_gltf

CORPUS = ("DamagedHelmet.glb", "WaterBottle.glb", "Avocado.glb")
SIZE = 2.0  # the largest side of an asset's bounding box once placed (about the helmet's)


def import_asset(path: Path) -> list:
    """The asset's mesh objects, imported, scaled so that its bounding box's largest side is SIZE, centred on the
    z axis and standing on z = 0."""
    bpy.ops.preferences.addon_enable(module="io_scene_gltf2")
    before = set(bpy.data.objects)
    import_gltf(path)
    new = [o for o in bpy.data.objects if o not in before]
    meshes = [o for o in new if o.type == "MESH"]
    bpy.context.view_layer.update()
    pts = [o.matrix_world @ v.co for o in meshes for v in o.data.vertices]
    lo = Vector((min(p.x for p in pts), min(p.y for p in pts), min(p.z for p in pts)))
    hi = Vector((max(p.x for p in pts), max(p.y for p in pts), max(p.z for p in pts)))
    s = SIZE / max(hi - lo)
    centre = Vector(((lo.x + hi.x) / 2, (lo.y + hi.y) / 2, lo.z))
    fit = Matrix.Scale(s, 4) @ Matrix.Translation(-centre)
    for o in new:
        if o.parent is None:
            o.matrix_world = fit @ o.matrix_world
    bpy.context.view_layer.update()
    return meshes


def corpus_scene(path: Path, width: int, height: int):
    from restircl.eval import blender_scenes as scenes

    sc = scenes.new_scene(width, height)
    import_asset(path)
    helmet_stage(sc)
    return sc


def compare(sc, cycles_spp: int, our_spp: int, bounces: int, out: Path) -> dict:
    """Scene sc rendered by Cycles and by F12 (its default still estimator, `our_spp` samples) with Light Paths of
    `bounces` bounces (0: direct light, eval/cycles/bridge.py direct_only), both written into `out`: relMSE, the
    image means' ratio and the seconds each took."""
    from restircl import Settings
    from restircl.eval import blender_scenes as scenes
    from restircl.eval.cycles.bridge import light_paths

    from .test_blender_support import ensure_registered, read_exr_passes, relmse, render_to

    ensure_registered()
    scenes.cycles_direct_only(sc, samples=cycles_spp, seed=1, threads=2)
    if bounces:
        light_paths(sc, Settings(max_bounces=bounces, diffuse_bounces=bounces, glossy_bounces=bounces))
    t0 = time.perf_counter()
    render_to(sc, out / "cycles.exr")
    t_cyc = time.perf_counter() - t0
    sc.render.engine = "RESTIRCL"
    sc.restircl.samples, sc.restircl.bake_resolution = our_spp, 64
    t0 = time.perf_counter()
    render_to(sc, out / "ours.exr")
    t_ours = time.perf_counter() - t0
    cyc = read_exr_passes(out / "cycles.exr")["Combined"][..., :3]
    ours = read_exr_passes(out / "ours.exr")["Combined"][..., :3]
    return {"relmse": relmse(ours, cyc), "mean_ratio": float(ours.mean() / cyc.mean()), "t_cycles": t_cyc,
            "t_ours": t_ours}


@dataclass
class Coverage:
    """One material's node types (bl_idname -> count) and how the export read each."""

    material: str
    counts: dict[str, int] = field(default_factory=dict)
    native: list[str] = field(default_factory=list)  # one entry per node
    baked: list[str] = field(default_factory=list)
    ignored: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def _upstream(tree, socket, seen: set) -> None:
    """Every node that feeds `socket`, through groups' outputs into their trees."""
    for link in socket.links:
        node = link.from_node
        if node.as_pointer() in seen:
            continue
        seen.add(node.as_pointer())
        if node.bl_idname == "ShaderNodeGroup" and node.node_tree is not None:
            out = next((n for n in node.node_tree.nodes if n.bl_idname == "NodeGroupOutput"), None)
            if out is not None:
                seen.add(out.as_pointer())
                for s in out.inputs:
                    _upstream(node.node_tree, s, seen)
        for s in node.inputs:
            if s.is_linked:
                _upstream(tree, s, seen)


def coverage(mat, warnings: list[str]) -> Coverage:
    """How the export (its `warnings`) read `mat`: a node type is baked where the bake warning names it (by its
    label), ignored where no node of that type feeds the Material Output's Surface, native otherwise."""
    from restircl_blender.export.nodes import node_label, output_node

    cov = Coverage(mat.name)
    tree = mat.node_tree
    used: set = set()
    out = output_node(tree)
    if out is not None:
        used.add(out.as_pointer())
        _upstream(tree, out.inputs["Surface"], used)
    mine = [w for w in warnings if f"material {mat.name!r}" in w]
    baked = {t.strip() for w in mine if "baked to images (node types:" in w
             for t in w.split("(node types:")[1].rstrip(")").split(",")}
    for n in tree.nodes:
        kind = n.bl_idname
        cov.counts[kind] = cov.counts.get(kind, 0) + 1
        how = cov.ignored if n.as_pointer() not in used else cov.baked if node_label(n) in baked else cov.native
        how.append(kind)
    cov.notes = [w.split(": ", 1)[1] for w in mine if "baked to images" not in w]
    return cov
