"""Light and shadow linking of a restircl Scene written into the bpy scene that bridge.to_bpy builds: each emitter
with links gets a receiver and a blocker collection of the named objects, with their link states (Blender 4.0+)."""

from __future__ import annotations

from ...scene.linking import Linking


def _collection(bpy, name: str, links: dict[str, str]):
    coll = bpy.data.collections.new(name)
    for obj_name, state in links.items():
        ob = bpy.data.objects.get(obj_name)
        if ob is None:
            continue
        coll.objects.link(ob)
        # collection_objects holds the entries in the order of coll.objects (an entry names no object)
        coll.collection_objects[list(coll.objects).index(ob)].light_linking.link_state = state
    return coll


def linking_to_bpy(bpy, emitters: list[tuple[str, Linking]]) -> None:
    """Give each emitter object (by name) the collections of its links."""
    for name, lk in emitters:
        ob = bpy.data.objects.get(name)
        if ob is None or lk.empty:
            continue
        if lk.receivers:
            ob.light_linking.receiver_collection = _collection(bpy, f"{name} receivers", lk.receivers)
        if lk.blockers:
            ob.light_linking.blocker_collection = _collection(bpy, f"{name} blockers", lk.blockers)
