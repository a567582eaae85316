"""Blender geometry -> restircl.Mesh: meshes with modifiers applied (and curves, text, metaballs through
`to_mesh`), collection and geometry-nodes instances (geometry read once per mesh datablock, one transform per
instance), the probes that tell whether an object deforms during an animation, and the vertices of objects that
deform within a still's shutter at their deformation steps (Mesh.deform, motion_blur.deform_frames).

Shading normals are the evaluated mesh's corner normals (Blender 4.1+: smooth and flat faces, sharp edges, the
Smooth by Angle modifier, custom normals), exported per triangle corner unless every face is flat. The UV map
(the active render one, as Cycles uses) is exported, per corner, for meshes whose materials read it."""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from ..light_groups import object_group
from .convert import matrix
from .linking import read_linking
from .material import MaterialTable
from .motion import Frames, fill_gaps, instance_key, transforms

GEOMETRY_TYPES = {"MESH", "CURVE", "CURVES", "SURFACE", "META", "FONT", "POINTCLOUD"}


@dataclass
class _Geometry:
    vertices: np.ndarray
    triangles: np.ndarray
    slot_ids: np.ndarray  # material slot per triangle
    materials: list  # Blender materials by slot
    uvs: np.ndarray | None = None  # (T, 3, 2) the active render UV map per corner
    uv_name: str = ""
    normals: np.ndarray | None = None  # (T, 3, 3) corner normals; None when every face is flat
    colors: dict | None = None  # colour attribute name -> (T, 3, 4) corner RGBA; "" also names the default one


@dataclass
class _Record:
    name: str
    vertices: np.ndarray
    triangles: np.ndarray
    material_ids: np.ndarray
    track: list  # object-to-world matrix per sampled frame
    uvs: np.ndarray | None = None
    normals: np.ndarray | None = None
    linking: object = None  # restircl Linking of the object as an emitter (export/linking.py), None: none
    lightgroup: str = ""  # its Light Group (light_groups.py)
    pass_index: int = 0  # Object > Relations > Pass Index (the Object Index pass)
    asset: str = ""  # the root of its parent chain (Cryptomatte's asset), "" when it has no parent
    colors: dict | None = None


class MeshReader:
    """The meshes of the current frame (`read`), then their matrices at the other frames (`sample`)."""

    def __init__(self, frames: Frames, materials: MaterialTable, warn: Callable[[str], None] = lambda _m: None,
                 deform: Callable[[object], list[int]] | None = None):
        """`deform(ob)`: the frames (among `frames`) at which object ob's deformation is read; None: nowhere."""
        self.frames = frames
        self._deform = deform
        # record -> frame index -> its vertices there, and its corner normals (smooth meshes)
        self._steps: dict[int, dict[int, tuple[np.ndarray, np.ndarray | None] | None]] = {}
        self._materials = materials
        self._warn = warn
        self._geometry: dict[int, _Geometry | None] = {}
        self._records: list[_Record] = []
        self._by_key: dict[tuple, int] = {}
        self._probes: dict[str, tuple[int, bytes]] = {}  # object -> (vertex count, digest) at the current frame
        self.deforming: list[str] = []  # objects whose geometry changes between frames
        self.deform_handled: list[str] = []  # objects whose deformation is read at its steps (or, by their
        # settings, not blurred)
        self.instances = 0

    def read(self, inst) -> None:
        ob = inst.object
        data = ob.data
        gkey = data.as_pointer() if data is not None and ob.type == "MESH" else ob.as_pointer()
        if gkey not in self._geometry or ob.type != "MESH":  # evaluated non-meshes are not shared
            self._geometry[gkey] = _read_geometry(ob)
        geo = self._geometry[gkey]
        if geo is None or len(geo.triangles) == 0:
            return
        n_slots = len(geo.materials)
        orig = ob.original if ob.original is not None else ob
        has_uv = geo.uvs is not None
        ids = np.array([self._materials.id_of(geo.materials[s] if n_slots and s < n_slots else None, orig, has_uv)
                        for s in range(max(n_slots, 1))], dtype=np.int64)
        tri_ids = ids[np.clip(geo.slot_ids, 0, len(ids) - 1)]
        uvs = geo.uvs if any(self._materials.uses_uv[i] for i in set(tri_ids.tolist())) else None
        for i in set(tri_ids.tolist()) if uvs is not None else ():
            for name in sorted(self._materials.uv_maps[i] - {geo.uv_name}):
                self._warn(f"object {ob.name!r}: material {self._materials.materials[i].name!r} names UV map "
                           f"{name!r}; the active render map {geo.uv_name!r} is used")
        colors = self._colors(ob, geo, tri_ids)
        if not inst.is_instance and may_deform(ob):
            self._probes[ob.name] = (len(geo.vertices), _digest(geo.vertices))
            self._read_steps(ob, geo)
        self._by_key[instance_key(inst)] = len(self._records)
        self._records.append(_Record(ob.name, geo.vertices, geo.triangles, tri_ids,
                                     self.frames.track(matrix(inst.matrix_world)), uvs, geo.normals,
                                     read_linking(ob), object_group(ob), int(getattr(ob, "pass_index", 0)),
                                     _asset(orig), colors))
        self.instances += int(inst.is_instance)

    def _read_steps(self, ob, geo: _Geometry) -> None:
        """Start reading the deformation steps of the object about to be recorded (its geometry here: `geo`)."""
        if self._deform is None:
            return
        self.deform_handled.append(ob.name)
        numbers = self.frames.numbers
        steps = sorted({numbers.index(f) for f in self._deform(ob) if f in numbers})
        here = self.frames.current_index
        if len(steps) > 1 or (steps and steps[0] != here):  # blurred, or read at another time than the frame
            self._steps[len(self._records)] = {k: (geo.vertices, geo.normals) if k == here else None for k in steps}

    def _colors(self, ob, geo: _Geometry, tri_ids: np.ndarray) -> dict | None:
        """The colour attributes the object's materials read (Attribute nodes); a name it has none of is said."""
        from restircl.upload.attributes import attribute_names

        names = attribute_names([self._materials.materials[i] for i in set(tri_ids.tolist())])
        for name in sorted(set(names) - set(geo.colors or {})):
            what = f"attribute {name!r}, which is not a colour attribute of it" if name else \
                "the default colour attribute, which it has not"
            self._warn(f"object {ob.name!r}: its materials read {what}: 0 is read")
        return {n: geo.colors[n] for n in names if n in (geo.colors or {})} or None

    def sample(self, inst, k: int) -> None:
        """The instance's matrix at frame index k; instances that appear only after the current frame are not
        exported (their geometry was never read)."""
        i = self._by_key.get(instance_key(inst))
        if i is None:
            return
        ob = inst.object
        self._records[i].track[k] = matrix(inst.matrix_world)
        probe = self._probes.get(ob.name)
        steps = self._steps.get(i)
        if steps is not None and k in steps:
            step = steps[k] = read_step(ob, self._records[i].normals is not None)
            if probe is not None and ob.name not in self.deforming and (
                    step is None or len(step[0]) != probe[0] or _digest(step[0]) != probe[1]):
                self.deforming.append(ob.name)
        elif probe is not None and ob.name not in self.deforming and _deformed(ob, probe):
            self.deforming.append(ob.name)

    @property
    def count(self) -> int:
        return len(self._records)

    def build(self) -> list:
        import restircl

        for r in self._records:
            fill_gaps(r.track)
        deform = {i: self._deformation(self._records[i], steps) for i, steps in self._steps.items()}
        return [restircl.Mesh(name=r.name, vertices=r.vertices, triangles=r.triangles, material_ids=r.material_ids,
                              transforms=transforms(r.track), uvs=r.uvs, normals=r.normals, attributes=r.colors,
                              **({} if r.linking is None else {"linking": r.linking}),
                              **({"lightgroup": r.lightgroup} if r.lightgroup else {}),
                              **({"pass_index": r.pass_index} if r.pass_index else {}),
                              **({"asset": r.asset} if r.asset else {}),
                              **(deform.get(i) or {})) for i, r in enumerate(self._records)]

    def _deformation(self, r: _Record, steps: dict[int, tuple[np.ndarray, np.ndarray | None] | None]) -> dict | None:
        """Mesh.deform, deform_times (and deform_normals) of a record from its steps; None where it does not deform,
        where its vertex count changes (then, as in Cycles, its deformation is not blurred: said), or where it has one
        step (its deformation not blurred: the record takes that step's vertices and normals)."""
        ks = sorted(steps)
        read = [steps[k] for k in ks]
        if any(s is None or s[0].shape != r.vertices.shape for s in read):
            self._warn(f"object {r.name!r} changes its vertex count within the shutter: its deformation is not "
                       "blurred (as in Cycles)")
            return None
        verts = [s[0] for s in read if s is not None]
        normals = [s[1] for s in read if s is not None]
        same_normals = r.normals is not None and all(n is not None and n.shape == r.normals.shape for n in normals)
        if len(ks) == 1:  # not blurred: the geometry at the one time it is read (the shutter's middle)
            r.vertices, r.normals = verts[0], normals[0] if same_normals else r.normals
            return None
        if all(np.array_equal(v, r.vertices) for v in verts):
            return None
        out = {"deform": np.stack(verts), "deform_times": np.array(ks, np.float64)}
        if same_normals:
            out["deform_normals"] = np.stack(normals)
        return out


def _asset(ob) -> str:
    """Cryptomatte's asset of an object: the root of its parent chain ("" for an object without a parent)."""
    root = ob
    while getattr(root, "parent", None) is not None:
        root = root.parent
    return root.name if root is not ob else ""


@contextmanager
def _evaluated_mesh(ob) -> Iterator:
    """The evaluated object's mesh (`to_mesh`), None where it has none, freed on leaving."""
    try:
        me = ob.to_mesh()
    except RuntimeError:
        me = None
    if me is None:
        yield None
        return
    try:
        yield me
    finally:
        ob.to_mesh_clear()


def _read_geometry(ob) -> _Geometry | None:
    with _evaluated_mesh(ob) as me:
        if me is None:
            return None
        me.calc_loop_triangles()
        nv, nt = len(me.vertices), len(me.loop_triangles)
        verts = np.empty(nv * 3, dtype=np.float32)
        me.vertices.foreach_get("co", verts)
        tris = np.empty(nt * 3, dtype=np.int32)
        me.loop_triangles.foreach_get("vertices", tris)
        slots = np.empty(nt, dtype=np.int32)
        me.loop_triangles.foreach_get("material_index", slots)
        if len(ob.material_slots):
            mats = [s.material for s in ob.material_slots]
        else:
            mats = list(me.materials)
        loops = np.empty(nt * 3, dtype=np.int64)
        me.loop_triangles.foreach_get("loops", loops)
        uvs, uv_name = _corner_uvs(me, loops)
        normals = _corner_normals(me, loops)
        colors = _corner_colors(me, loops)
    return _Geometry(verts.reshape(-1, 3).astype(np.float64), tris.reshape(-1, 3).astype(np.int64),
                     slots.astype(np.int64), mats, uvs, uv_name, normals, colors)


def read_step(ob, normals: bool) -> tuple[np.ndarray, np.ndarray | None] | None:
    """The evaluated object's (V, 3) object-space vertices (a deformation step) and, with `normals`, its corner
    normals per triangle (None when every face is flat); None: it has no mesh."""
    with _evaluated_mesh(ob) as me:
        if me is None:
            return None
        verts = np.empty(len(me.vertices) * 3, dtype=np.float32)
        me.vertices.foreach_get("co", verts)
        corner = None
        if normals:
            me.calc_loop_triangles()
            loops = np.empty(len(me.loop_triangles) * 3, dtype=np.int64)
            me.loop_triangles.foreach_get("loops", loops)
            corner = _corner_normals(me, loops)
    return verts.reshape(-1, 3).astype(np.float64), corner


def _corner_colors(me, loops: np.ndarray) -> dict | None:
    """The mesh's colour attributes (point or corner domain; Blender gives byte colours in linear light too) per
    triangle corner; the default one (Color Attribute nodes with no name read it) also under ""."""
    attrs = getattr(me, "color_attributes", None)
    if attrs is None or not len(attrs):
        return None
    vert_of_loop = np.empty(len(me.loops), dtype=np.int64)
    me.loops.foreach_get("vertex_index", vert_of_loop)
    out = {}
    for a in attrs:
        if a.domain not in ("POINT", "CORNER"):
            continue
        buf = np.empty(len(a.data) * 4, dtype=np.float32)
        a.data.foreach_get("color", buf)
        per = buf.reshape(-1, 4)
        idx = loops if a.domain == "CORNER" else vert_of_loop[loops]
        out[a.name] = per[idx].reshape(-1, 3, 4).astype(np.float64)
    default = getattr(attrs, "default_color_name", "") or ""
    if default in out:
        out[""] = out[default]
    return out or None


def _corner_uvs(me, loops: np.ndarray) -> tuple[np.ndarray | None, str]:
    layers = list(me.uv_layers)
    layer = next((u for u in layers if u.active_render), None) or me.uv_layers.active
    if layer is None or len(me.loops) == 0:
        return None, ""
    uv = np.empty(len(me.loops) * 2, dtype=np.float32)
    if hasattr(layer, "uv"):
        layer.uv.foreach_get("vector", uv)
    else:  # before 3.5
        layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)[loops].reshape(-1, 3, 2).astype(np.float64), layer.name


def _corner_normals(me, loops: np.ndarray) -> np.ndarray | None:
    """Blender 4.1+ corner normals (which honour smooth/flat faces, sharp edges and custom normals); None when
    every face is flat, where the geometric normal is the shading normal."""
    if getattr(me, "normals_domain", "CORNER") == "FACE" or len(me.loops) == 0:
        return None
    n = np.empty(len(me.loops) * 3, dtype=np.float32)
    if hasattr(me, "corner_normals"):
        me.corner_normals.foreach_get("vector", n)
    else:  # before 4.1
        me.calc_normals_split()
        me.loops.foreach_get("normal", n)
    return n.reshape(-1, 3)[loops].reshape(-1, 3, 3).astype(np.float64)


def _digest(arr: np.ndarray) -> bytes:
    return hashlib.blake2b(np.ascontiguousarray(arr, dtype=np.float32).tobytes(), digest_size=16).digest()


def may_deform(ob) -> bool:
    """Whether the object's geometry may change with time: not a plain mesh, or modifiers, shape keys or animated
    mesh data."""
    orig = ob.original if ob.original is not None else ob
    if ob.type != "MESH":
        return True
    if len(orig.modifiers):
        return True
    keys = getattr(orig.data, "shape_keys", None)
    if keys is not None:
        return True
    ad = getattr(orig.data, "animation_data", None)
    return ad is not None and (ad.action is not None or len(ad.drivers) > 0)


def _deformed(ob, probe: tuple[int, bytes]) -> bool:
    geo = _read_geometry(ob)
    if geo is None:
        return probe[0] != 0
    return len(geo.vertices) != probe[0] or _digest(geo.vertices) != probe[1]
