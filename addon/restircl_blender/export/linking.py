"""Blender's light and shadow linking (4.0+: Object > Shading > Light Linking / Shadow Linking) -> restircl
Linking: the receiver and blocker collections of an emitter object (a light, or a mesh whose material emits), each
object in them with its link state, by object name (the names the mesh export gives). Objects of a child
collection take the child collection's state."""

from __future__ import annotations


def collection_states(coll) -> dict[str, str]:
    """Object name -> INCLUDE | EXCLUDE of a linking collection (None: no collection, no links)."""
    out: dict[str, str] = {}
    if coll is None:
        return out
    # collection_objects and collection_children hold the link states in the order of objects and children
    for ob, entry in zip(coll.objects, coll.collection_objects, strict=False):
        out[ob.name] = entry.light_linking.link_state
    for child, entry in zip(coll.children, coll.collection_children, strict=False):
        for ob in child.all_objects:
            out.setdefault(ob.name, entry.light_linking.link_state)
    return out


def read_linking(ob):
    """The restircl Linking of emitter object `ob` (evaluated or original), or None where it links nothing (or the
    Blender release has no light linking)."""
    orig = ob.original if getattr(ob, "original", None) is not None else ob
    ll = getattr(orig, "light_linking", None)
    if ll is None:
        return None
    receivers, blockers = collection_states(ll.receiver_collection), collection_states(ll.blocker_collection)
    if not receivers and not blockers:
        return None
    from restircl.scene.linking import Linking

    return Linking(receivers=receivers, blockers=blockers)
