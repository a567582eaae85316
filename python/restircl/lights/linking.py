"""Light linking and shadow linking on the device (scene/linking.py describes them; opencl/lights/linking.h reads them).

Every object (mesh) belongs to one receiver light set and one blocker set: set 0 holds the objects that no emitter
names; each further set the objects that the emitters name alike (the same state in every emitter's collection).
Every emitter then has a 64-bit mask of the receiver sets it lights and one of the blocker sets that shadow it:
set k is in its receiver mask when the emitter INCLUDEs the set's objects, or, where its collection holds no
INCLUDE at all, when it does not EXCLUDE them; the same for blockers. As in Cycles, at most 64 sets of each kind
(the default one included): a scene that needs more raises SceneError.

Device layout (no new buffer, no new kernel argument):
- Tri.e2.w (int bits): the object id in bits 0..19, its receiver set in bits 20..25, its blocker set in 26..31.
- Light.L.w (flags): bits 8..31 the index, in Light records from the start of the light buffer, of the emitter's
  link record (0: lights every set and is shadowed by every one, no record read); the link records follow the
  light buffer's data, each holding (receiver mask lo, hi, blocker mask lo, hi) as uint bits in its p lanes, and
  the emitter's light group (lights/light_groups.py; -1: none) in a.x.
  FLAG_SHADOW_LINKED marks an emitter whose blocker mask is not all sets: BSDF rays do not look for it (its light
  comes from light sampling alone, with MIS weight 1), since such a ray stops at an object that does not shadow it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene.errors import SceneError
from ..scene.linking import Linking
from .record import LANES

MAX_SETS = 64
OBJECT_BITS = 20  # object ids below 2^20 when the scene links lights
RECEIVER_SHIFT = 20
BLOCKER_SHIFT = 26
LINK_SHIFT = 8  # L.w bits from here: the link record's index
FLAG_SHADOW_LINKED = 64  # a bit of its own among the LIGHT_FLAG_* (lights/record.py)
ALL_SETS = (1 << MAX_SETS) - 1


@dataclass
class LinkSets:
    """The sets of a scene: per mesh its receiver and blocker set, per emitter its two masks."""

    receiver_set: np.ndarray  # (meshes,) int
    blocker_set: np.ndarray  # (meshes,) int
    light_masks: list[tuple[int, int]]  # per scene light: (receiver mask, blocker mask)
    mesh_masks: list[tuple[int, int]]  # per mesh as an emitter (its emissive triangles)


def scene_links(scene) -> list[Linking]:
    """Every emitter's links: the scene's lights, then its meshes."""
    return [lt.linking for lt in scene.lights] + [m.linking for m in scene.meshes]


def uses_linking(scene) -> bool:
    return any(not lk.empty for lk in scene_links(scene))


def _sets(names: list[str], collections: list[dict[str, str]], kind: str) -> tuple[np.ndarray, list[int]]:
    """The set of each object and the mask of each emitter for one kind of link (receivers or blockers)."""
    signatures: dict[tuple, int] = {}
    object_set = np.zeros(len(names), np.int64)
    default = tuple([None] * len(collections))
    for k, name in enumerate(names):
        sig = tuple(c.get(name) for c in collections)
        if sig == default:
            continue
        object_set[k] = signatures.setdefault(sig, len(signatures) + 1)
    if len(signatures) + 1 > MAX_SETS:
        raise SceneError(f"light linking: the {kind} need {len(signatures) + 1} sets of objects; at most {MAX_SETS}"
                         " are supported (as in Cycles)")
    masks = []
    for e, coll in enumerate(collections):
        exclusive = "INCLUDE" in coll.values()
        keep = "INCLUDE" if exclusive else "EXCLUDE"
        named = 0
        for sig, s in signatures.items():
            if sig[e] == keep:
                named |= 1 << s
        # exclusive: the sets it includes; else every set (those without objects too) but the ones it excludes
        masks.append(named if exclusive else ALL_SETS & ~named)
    return object_set, masks


def link_sets(scene) -> LinkSets:
    """The sets and masks of `scene` (SceneError where it needs more than MAX_SETS of a kind)."""
    links = scene_links(scene)
    names = [m.name for m in scene.meshes]
    recv_set, recv_masks = _sets(names, [lk.receivers for lk in links], "receivers")
    block_set, block_masks = _sets(names, [lk.blockers for lk in links], "blockers")
    pairs = list(zip(recv_masks, block_masks, strict=True))
    n = len(scene.lights)
    return LinkSets(recv_set, block_set, pairs[:n], pairs[n:])


def object_bits(scene, obj: np.ndarray) -> np.ndarray:
    """Tri.e2.w's int value for triangles of objects `obj` (mesh indices): the object id, and with linking its
    receiver and blocker sets."""
    obj = np.asarray(obj, np.int64)
    if not uses_linking(scene):
        return obj.astype(np.int32)
    if len(scene.meshes) > 1 << OBJECT_BITS:
        raise SceneError(f"light linking: at most {1 << OBJECT_BITS} objects, the scene has {len(scene.meshes)}")
    sets = link_sets(scene)
    bits = obj | (sets.receiver_set[obj] << RECEIVER_SHIFT) | (sets.blocker_set[obj] << BLOCKER_SHIFT)
    return bits.astype(np.uint32).view(np.int32)


def emitter_masks(scene, source: np.ndarray, tri_object: np.ndarray) -> list[tuple[int, int]]:
    """(receiver mask, blocker mask) of each device light by its source (DeviceLights.source: a scene light, the
    world, or -1 - an emissive triangle of the world, whose mesh tri_object names)."""
    sets = link_sets(scene)
    out = []
    for src in np.asarray(source, np.int64).tolist():
        if 0 <= src < len(scene.lights):
            out.append(sets.light_masks[src])
        elif src < 0:
            out.append(sets.mesh_masks[int(tri_object[-1 - src])])
        else:  # the world: Blender links no world
            out.append((ALL_SETS, ALL_SETS))
    return out


def link_records(records: np.ndarray, data: np.ndarray, masks: list[tuple[int, int]],
                 groups: list[int] | None = None) -> np.ndarray:
    """Flag `records` (layouts.LIGHT, in place) with their link records' indices and return the light buffer's data
    with those records after it (padded to whole records). `groups`: each light's light group (lights/light_groups.py,
    -1: none), kept in its record's a.x."""
    groups = groups if groups is not None else [-1] * len(masks)
    flat = records.view(np.float32).reshape(-1, LANES)
    flags = flat[:, 15].copy().view(np.uint32)
    pad = (-len(data)) % LANES
    first = len(records) + (len(data) + pad) // LANES
    table: dict[tuple[int, int, int], int] = {}
    for i, ((recv, block), group) in enumerate(zip(masks, groups, strict=True)):
        if recv == ALL_SETS and block == ALL_SETS and group < 0:
            continue
        index = table.setdefault((recv, block, group), first + len(table))
        if index >= 1 << (32 - LINK_SHIFT):
            raise SceneError("light linking: the light buffer is too large for its link records")
        flags[i] |= np.uint32(index << LINK_SHIFT)
        if block != ALL_SETS:
            flags[i] |= np.uint32(FLAG_SHADOW_LINKED)
    flat[:, 15] = flags.view(np.float32)
    if not table:
        return data
    rows = np.zeros((len(table), LANES), np.uint32)
    for (recv, block, group), index in table.items():
        rows[index - first, 0:5] = [recv & 0xFFFFFFFF, recv >> 32, block & 0xFFFFFFFF, block >> 32, group & 0xFFFFFFFF]
    return np.concatenate([data, np.zeros(pad, np.float32), rows.view(np.float32).reshape(-1)])
