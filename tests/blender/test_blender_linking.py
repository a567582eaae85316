"""Light and shadow linking through the add-on: a Blender scene whose light lights one object only (a receiver
collection with an INCLUDE entry), is not shadowed by a plank (a blocker collection with an EXCLUDE entry), and
whose emissive panel leaves the plank out (a mesh emitter's receiver collection); the export gives each its
restircl Linking, and an F12 render agrees with Cycles'. Unlinked, the same F12 render differs from it."""

from __future__ import annotations

import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import cycles_and_ours, ensure_registered, needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

BOUND = 0.01


def _collection(name: str, states: dict) -> bpy.types.Collection:
    coll = bpy.data.collections.new(name)
    for ob, state in states.items():
        coll.objects.link(ob)
        coll.collection_objects[list(coll.objects).index(ob)].light_linking.link_state = state
    return coll


def linked_scene(linked: bool = True):
    sc = scenes.new_scene(48, 36)
    grey = scenes.diffuse_material("Grey", (0.6, 0.6, 0.6))
    floor_a = scenes.quad("floor_a", 3.0, 5.0, grey, location=(-1.5, 0.5, 0.0))
    floor_b = scenes.quad("floor_b", 3.0, 5.0, grey, location=(1.5, 0.5, 0.0))
    plank = scenes.quad("plank", 1.2, 1.2, grey, location=(-1.2, 0.2, 0.9))
    glow = scenes.quad("glow", 2.0, 1.0, scenes.emission_material("Glow", (1.0, 0.8, 0.5), 3.0),
                       location=(0.0, 2.5, 0.8), rotation=(1.5708, 0, 0))
    key = scenes.light("POINT", "key", (-1.2, 0.2, 2.2), energy=150.0, shadow_soft_size=0.15)
    scenes.light("AREA", "fill", (1.4, 0.5, 2.5), energy=120.0, size=0.6)
    scenes.camera((0.0, -5.5, 4.5), (0.0, 0.4, 0.3), lens=30.0)
    if linked:
        key.light_linking.receiver_collection = _collection("key receivers", {floor_a: "INCLUDE"})
        key.light_linking.blocker_collection = _collection("key blockers", {plank: "EXCLUDE"})
        glow.light_linking.receiver_collection = _collection("glow receivers", {plank: "EXCLUDE"})
    assert floor_b.name == "floor_b"
    return sc


def test_the_export_reads_the_links():
    ensure_registered()
    from restircl_blender.export.scene import export_scene

    sc = linked_scene()
    ex = export_scene(bpy.context.evaluated_depsgraph_get())
    lights = {lt.name: lt for lt in ex.scene.lights}
    meshes = {m.name: m for m in ex.scene.meshes}
    assert lights["key"].linking.receivers == {"floor_a": "INCLUDE"}
    assert lights["key"].linking.blockers == {"plank": "EXCLUDE"}
    assert lights["fill"].linking.empty
    assert meshes["glow"].linking.receivers == {"plank": "EXCLUDE"} and not meshes["glow"].linking.blockers
    assert meshes["floor_a"].linking.empty
    assert sc.camera is not None


@pytest.mark.parametrize("linked", [True, False], ids=["linked", "unlinked"])
def test_f12_with_links_agrees_with_cycles(tmp_path, monkeypatch, linked, record_property):
    sc = linked_scene()
    if not linked:  # the negative control: restircl renders the scene with the links left out of the export
        ensure_registered()
        from restircl_blender.export import light, mesh

        monkeypatch.setattr(light, "read_linking", lambda _ob: None)
        monkeypatch.setattr(mesh, "read_linking", lambda _ob: None)
    err, _ = cycles_and_ours(tmp_path, sc, 256, 256, f"restircl {'with' if linked else 'without'} the links")
    record_property("relmse", err)
    assert (err < BOUND) == linked
