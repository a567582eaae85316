"""Evaluated Blender depsgraph -> restircl.Scene.

Geometry (meshes with modifiers applied, collection and geometry-nodes instances) is read once, at the first
frame asked for; transforms of every instance, light and the camera are sampled at each frame asked for, so an
animation render exports its geometry once and its motion as per-frame matrices. Light units follow Cycles, as
measured in docs/units.md: lights keep Blender's power (W) or sun strength (W/m^2); the exporter folds in what
Blender layers on top of it (colour temperature, exposure, the 'normalize' switch, a light node tree's Emission
strength).

Everything that cannot be represented becomes a warning in `Export.warnings` (the engine shows them with
`RenderEngine.report`); a scene that cannot be rendered at all raises ExportError.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

DEFAULT_ALBEDO = (0.8, 0.8, 0.8)  # Cycles' surface for objects without a material
GEOMETRY_TYPES = {"MESH", "CURVE", "CURVES", "SURFACE", "META", "FONT", "POINTCLOUD"}
BLENDER_SPREAD_FULL = math.pi - 1e-4


class ExportError(Exception):
    """The Blender scene cannot be exported (no camera, unsupported camera type, ...)."""


@dataclass
class Export:
    scene: object  # restircl.Scene
    frames: list[int]  # Blender frame number of each scene frame index
    warnings: list[str] = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    deforming: list[str] = field(default_factory=list)  # objects whose geometry changes between frames

    def index_of(self, frame: int) -> int:
        """Scene frame index of a Blender frame (the last sampled frame at or before it)."""
        best = 0
        for i, f in enumerate(self.frames):
            if f <= frame:
                best = i
        return best

    def fingerprint(self) -> str:
        """A hash of everything exported: equal fingerprints mean an identical scene."""
        h = hashlib.blake2b(digest_size=16)
        sc = self.scene
        for mesh in sc.meshes:
            for arr in (mesh.vertices, mesh.triangles, mesh.material_ids, mesh.transforms):
                h.update(np.ascontiguousarray(arr).tobytes())
        for mat in sc.materials:
            h.update(repr((mat.albedo, mat.emission, mat.emission_strength)).encode())
        for lt in sc.lights:
            h.update(repr((lt.type, lt.color, lt.power, lt.radius, lt.spot_size, lt.spot_blend, lt.angle,
                           lt.shape, lt.size, lt.size_y)).encode())
            h.update(np.ascontiguousarray(lt.transforms).tobytes())
            if lt.power_per_frame is not None:
                h.update(np.ascontiguousarray(lt.power_per_frame).tobytes())
        cam = sc.camera
        if cam is not None:
            h.update(repr((cam.width, cam.height, cam.lens, cam.sensor_width, cam.sensor_height, cam.sensor_fit,
                           cam.shift_x, cam.shift_y, cam.cuts)).encode())
            h.update(np.ascontiguousarray(cam.transforms).tobytes())
        h.update(repr(self.frames).encode())
        return h.hexdigest()


# ---- small helpers -----------------------------------------------------------------------------------


def _matrix(m) -> np.ndarray:
    return np.array([list(row) for row in m], dtype=np.float64)


def _rgb(v) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


def _orthonormal(m: np.ndarray) -> np.ndarray:
    """Drop scale (and shear) from an object matrix, keeping its rotation, mirroring and position."""
    out = np.array(m, dtype=np.float64)
    for i in range(3):
        n = np.linalg.norm(out[:3, i])
        if n > 0 and np.isfinite(n):
            out[:3, i] /= n
    return out


def render_resolution(scene) -> tuple[int, int]:
    r = scene.render
    return (max(1, int(r.resolution_x * r.resolution_percentage / 100)),
            max(1, int(r.resolution_y * r.resolution_percentage / 100)))


# ---- materials ---------------------------------------------------------------------------------------


class _MaterialReader:
    """Diffuse albedo and emitted radiance of a Blender material, read from its node tree."""

    def __init__(self, warn: Callable[[str], None]):
        self.warn = warn

    def read(self, mat) -> tuple[tuple, tuple, float]:
        """(albedo, emission colour, emission strength)."""
        if mat is None:
            return DEFAULT_ALBEDO, (0.0, 0.0, 0.0), 0.0
        if mat.node_tree is None:  # (Material.use_nodes is deprecated in Blender 5: node trees always exist)
            return _rgb(mat.diffuse_color), (0.0, 0.0, 0.0), 0.0
        tree = mat.node_tree
        out = None
        for target in ("CYCLES", "ALL"):
            try:
                out = tree.get_output_node(target)
            except (TypeError, RuntimeError):
                out = None
            if out is not None:
                break
        if out is None:
            self.warn(f"material {mat.name!r}: no Material Output node; rendered black")
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 0.0
        albedo, emission = self._shader(self._source(out.inputs["Surface"]), mat.name, depth=0)
        albedo = tuple(float(np.clip(a, 0.0, 1.0)) for a in albedo)
        emission = np.maximum(np.asarray(emission, dtype=np.float64), 0.0)
        strength = float(emission.max())
        colour = tuple(float(c / strength) for c in emission) if strength > 0 else (0.0, 0.0, 0.0)
        return albedo, colour, strength

    @staticmethod
    def _source(socket):
        """The node feeding `socket` (through reroutes), or None."""
        while socket is not None and socket.is_linked:
            link = socket.links[0]
            if not link.is_valid or link.is_muted:
                return None
            node = link.from_node
            if node.bl_idname == "NodeReroute":
                socket = node.inputs[0]
                continue
            return node
        return None

    def _colour(self, node, names: Sequence[str], mat_name: str) -> np.ndarray:
        for name in names:
            sock = node.inputs.get(name)
            if sock is None:
                continue
            if not sock.is_linked:
                v = sock.default_value
                return np.array([v[0], v[1], v[2]], dtype=np.float64) if hasattr(v, "__len__") else np.full(3, v)
            src = self._source(sock)
            if src is not None and src.bl_idname == "ShaderNodeRGB":
                v = src.outputs[0].default_value
                return np.array([v[0], v[1], v[2]], dtype=np.float64)
            v = sock.default_value
            self.warn(f"material {mat_name!r}: {node.name} input {name!r} is driven by "
                      f"{src.bl_idname if src else 'a link'}; its unlinked value is used")
            return np.array([v[0], v[1], v[2]], dtype=np.float64)
        return np.array(DEFAULT_ALBEDO)

    def _value(self, node, name: str, mat_name: str, default: float = 0.0) -> float:
        sock = node.inputs.get(name)
        if sock is None:
            return default
        if sock.is_linked:
            src = self._source(sock)
            if src is not None and src.bl_idname == "ShaderNodeValue":
                return float(src.outputs[0].default_value)
            self.warn(f"material {mat_name!r}: {node.name} input {name!r} is linked; its unlinked value is used")
        return float(sock.default_value)

    def _shader(self, node, mat_name: str, depth: int) -> tuple[np.ndarray, np.ndarray]:
        zero = np.zeros(3)
        if node is None or depth > 32:
            return zero, zero
        kind = node.bl_idname
        if node.mute:
            self.warn(f"material {mat_name!r}: muted node {node.name!r} is ignored")
            return zero, zero
        if kind == "ShaderNodeBsdfDiffuse":
            return self._colour(node, ("Color",), mat_name), zero
        if kind == "ShaderNodeBsdfPrincipled":
            albedo = self._colour(node, ("Base Color",), mat_name)
            emission = self._colour(node, ("Emission Color", "Emission"), mat_name) * self._value(
                node, "Emission Strength", mat_name, 1.0)
            for name in ("Metallic", "Transmission Weight", "Transmission"):
                if name in node.inputs and self._value(node, name, mat_name) > 0:
                    self.warn(f"material {mat_name!r}: Principled {name} is not supported; "
                              "the base colour is rendered as diffuse")
                    break
            return albedo, emission
        if kind == "ShaderNodeEmission":
            return zero, self._colour(node, ("Color",), mat_name) * self._value(node, "Strength", mat_name, 1.0)
        if kind == "ShaderNodeAddShader":
            a = self._shader(self._source(node.inputs[0]), mat_name, depth + 1)
            b = self._shader(self._source(node.inputs[1]), mat_name, depth + 1)
            return a[0] + b[0], a[1] + b[1]
        if kind == "ShaderNodeMixShader":
            fac = float(np.clip(self._value(node, "Fac", mat_name, 0.5), 0.0, 1.0))
            a = self._shader(self._source(node.inputs[1]), mat_name, depth + 1)
            b = self._shader(self._source(node.inputs[2]), mat_name, depth + 1)
            return (1 - fac) * a[0] + fac * b[0], (1 - fac) * a[1] + fac * b[1]
        if kind == "ShaderNodeGroup":
            self.warn(f"material {mat_name!r}: node group {node.name!r} is not supported; rendered grey")
            return np.array(DEFAULT_ALBEDO), zero
        names = [n for n in ("Color", "Base Color") if n in node.inputs]
        if names:
            self.warn(f"material {mat_name!r}: {node.bl_label or kind} is not supported; its colour is "
                      "rendered as diffuse")
            return self._colour(node, names, mat_name), zero
        self.warn(f"material {mat_name!r}: {node.bl_label or kind} is not supported; rendered grey")
        return np.array(DEFAULT_ALBEDO), zero


# ---- lights ------------------------------------------------------------------------------------------


def _light_params(ld, scale: np.ndarray, warn: Callable[[str], None], name: str) -> dict:
    """restircl.Light keyword arguments (without transforms) for a Blender light datablock."""
    colour = np.array(_rgb(ld.color))
    if getattr(ld, "use_temperature", False):
        colour = colour * np.array(_rgb(ld.temperature_color))
    power = float(ld.energy) * 2.0 ** float(getattr(ld, "exposure", 0.0))
    if getattr(ld, "use_nodes", False) and ld.node_tree is not None:
        factor = _light_node_factor(ld.node_tree, warn, name)
        colour = colour * factor[0]
        power *= factor[1]
    kind = ld.type
    params: dict = {"name": name}
    if kind in ("POINT", "SPOT"):
        params["type"] = kind.lower()
        params["radius"] = float(ld.shadow_soft_size)
        if kind == "SPOT":
            params["spot_size"] = float(ld.spot_size)
            params["spot_blend"] = float(ld.spot_blend)
            if getattr(ld, "use_square", False):
                warn(f"light {name!r}: square spot cones are rendered round")
        r = params["radius"]
        if not getattr(ld, "normalize", True):
            power *= 4.0 * math.pi * r * r if r > 0 else 4.0
        params["soft_falloff"] = bool(getattr(ld, "use_soft_falloff", False))
    elif kind == "SUN":
        params["type"] = "sun"
        params["angle"] = float(ld.angle)
        if not getattr(ld, "normalize", True):
            power *= math.pi * math.sin(float(ld.angle) / 2.0) ** 2
    elif kind == "AREA":
        params["type"] = "area"
        params["shape"] = ld.shape
        params["size"] = float(ld.size)
        params["size_y"] = float(ld.size_y) if ld.shape in ("RECTANGLE", "ELLIPSE") else float(ld.size)
        if float(getattr(ld, "spread", math.pi)) < BLENDER_SPREAD_FULL:
            warn(f"light {name!r}: area light spread below 180 degrees is rendered as 180 degrees")
        if not getattr(ld, "normalize", True):
            sx, sy = params["size"] * scale[0], params["size_y"] * scale[1]
            area = sx * sy * (math.pi / 4.0 if ld.shape in ("DISK", "ELLIPSE") else 1.0)
            power *= area
    else:
        raise ExportError(f"light {name!r}: unknown light type {kind!r}")
    params["color"] = _rgb(colour)
    params["power"] = power
    return params


def _light_node_factor(tree, warn: Callable[[str], None], name: str) -> tuple[np.ndarray, float]:
    """(colour, strength) of the Emission node feeding a light's node tree output."""
    out = None
    for node in tree.nodes:
        if node.bl_idname == "ShaderNodeOutputLight" and getattr(node, "is_active_output", True):
            out = node
            break
    if out is None or not out.inputs["Surface"].is_linked:
        return np.ones(3), 1.0
    src = out.inputs["Surface"].links[0].from_node
    if src.bl_idname != "ShaderNodeEmission":
        warn(f"light {name!r}: light node {src.bl_label!r} is not supported; ignored")
        return np.ones(3), 1.0
    col, strength = src.inputs["Color"], src.inputs["Strength"]
    if col.is_linked or strength.is_linked:
        warn(f"light {name!r}: textured light nodes are not supported; their unlinked values are used")
    return np.array(_rgb(col.default_value)), float(strength.default_value)


# ---- camera -------------------------------------------------------------------------------------------


def _camera_params(cam_obj, scene, warn: Callable[[str], None]) -> dict:
    cd = cam_obj.data
    if cd.type == "ORTHO":
        raise ExportError(f"camera {cam_obj.name!r}: orthographic cameras are not supported; "
                          "use a perspective camera")
    if cd.type != "PERSP":
        kind = {"PANO": "panoramic"}.get(cd.type, cd.type.lower())
        raise ExportError(f"camera {cam_obj.name!r}: {kind} cameras are not supported; use a perspective camera")
    w, h = render_resolution(scene)
    r = scene.render
    if abs(r.pixel_aspect_x - r.pixel_aspect_y) > 1e-6:
        warn("non-square pixel aspect is rendered with square pixels")
    if getattr(cd, "dof", None) is not None and cd.dof.use_dof:
        warn(f"camera {cam_obj.name!r}: depth of field is not rendered")
    return {
        "width": w, "height": h, "lens": float(cd.lens), "sensor_width": float(cd.sensor_width),
        "sensor_height": float(cd.sensor_height), "sensor_fit": cd.sensor_fit,
        "shift_x": float(cd.shift_x), "shift_y": float(cd.shift_y),
    }


# ---- the export ---------------------------------------------------------------------------------------


@dataclass
class _Geometry:
    vertices: np.ndarray
    triangles: np.ndarray
    slot_ids: np.ndarray  # material slot per triangle
    materials: list  # Blender materials by slot


def _read_geometry(ob) -> _Geometry | None:
    try:
        me = ob.to_mesh()
    except RuntimeError:
        return None
    if me is None:
        return None
    try:
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
    finally:
        ob.to_mesh_clear()
    return _Geometry(verts.reshape(-1, 3).astype(np.float64), tris.reshape(-1, 3).astype(np.int64),
                     slots.astype(np.int64), mats)


def _instance_key(inst) -> tuple:
    ob = inst.object
    parent = inst.parent.original.name if inst.is_instance and inst.parent is not None else ""
    return (ob.original.name if ob.original is not None else ob.name, parent,
            tuple(inst.persistent_id) if inst.is_instance else ())


def export_scene(depsgraph, frames: Sequence[int] | None = None,
                 frame_set: Callable[[int], None] | None = None, camera=None) -> Export:
    """Export the evaluated scene.

    `frames` are the Blender frame numbers to sample motion at (default: only the current frame); it must
    contain the current frame, where the geometry is read. `frame_set(frame)` moves the depsgraph to a frame
    (RenderEngine.frame_set or Scene.frame_set); the depsgraph is moved back to the current frame at the end.
    `camera` overrides the scene camera (an evaluated camera object)."""
    import restircl

    scene = depsgraph.scene
    current = int(scene.frame_current)
    frames = [current] if not frames else sorted({int(f) for f in frames})
    if current not in frames:
        raise ExportError(f"export_scene: the current frame {current} is not among the frames {frames}")
    if len(frames) > 1 and frame_set is None:
        raise ExportError("export_scene: frame_set is needed to sample more than one frame")
    warnings: list[str] = []

    def warn(msg: str) -> None:
        if msg not in warnings:
            warnings.append(msg)

    reader = _MaterialReader(warn)
    mat_index: dict[object, int] = {}
    materials: list = []

    def material_id(mat) -> int:
        key = mat.original.name if mat is not None and mat.original is not None else (
            mat.name if mat is not None else None)
        if key not in mat_index:
            albedo, colour, strength = reader.read(mat)
            mat_index[key] = len(materials)
            materials.append(restircl.Material(name=key or "(none)", albedo=albedo, emission=colour,
                                               emission_strength=strength))
        return mat_index[key]

    # ---- the current frame: geometry, materials, lights, camera
    geometry_cache: dict[int, _Geometry | None] = {}
    mesh_keys: list[tuple] = []
    mesh_records: list[tuple[str, np.ndarray, np.ndarray, np.ndarray]] = []
    deform_probe: dict[int, tuple[str, int, bytes]] = {}  # mesh index -> (object, vertex count, digest)
    light_keys: list[tuple] = []
    light_params: list[dict] = []
    n_instances = 0
    cur_mesh_mats: list[np.ndarray] = []
    cur_light_mats: list[np.ndarray] = []
    for inst in depsgraph.object_instances:
        ob = inst.object
        if ob.type in GEOMETRY_TYPES:
            data = ob.data
            gkey = data.as_pointer() if data is not None and ob.type == "MESH" else ob.as_pointer()
            if gkey not in geometry_cache or ob.type != "MESH":
                geometry_cache[gkey] = _read_geometry(ob)
            geo = geometry_cache[gkey]
            if geo is None or len(geo.triangles) == 0:
                continue
            n_slots = len(geo.materials)
            ids = np.array([material_id(geo.materials[s] if n_slots and s < n_slots else None)
                            for s in range(max(n_slots, 1))], dtype=np.int64)
            tri_ids = ids[np.clip(geo.slot_ids, 0, len(ids) - 1)]
            if not inst.is_instance and _may_deform(ob):
                deform_probe[len(mesh_keys)] = (ob.name, len(geo.vertices), _digest(geo.vertices))
            mesh_keys.append(_instance_key(inst))
            mesh_records.append((ob.name, geo.vertices, geo.triangles, tri_ids))
            cur_mesh_mats.append(_matrix(inst.matrix_world))
            n_instances += int(inst.is_instance)
        elif ob.type == "LIGHT":
            m = _matrix(inst.matrix_world)
            params = _light_params(ob.data, np.linalg.norm(m[:3, :3], axis=0), warn, ob.name)
            light_keys.append(_instance_key(inst))
            light_params.append(params)
            cur_light_mats.append(m)
    cam_obj = camera if camera is not None else scene.camera
    if cam_obj is None:
        raise ExportError("the scene has no camera; add one and make it the active camera")
    cam_params = _camera_params(cam_obj, scene, warn)

    # ---- every frame: motion (and light power) only
    n_f = len(frames)
    k_cur = frames.index(current)
    mesh_mats = [[None] * n_f for _ in mesh_keys]
    light_mats = [[None] * n_f for _ in light_keys]
    light_powers = [[0.0] * n_f for _ in light_keys]
    cam_mats: list = [None] * n_f
    cam_names: list = [None] * n_f
    for i, m in enumerate(cur_mesh_mats):
        mesh_mats[i][k_cur] = m
    for i, m in enumerate(cur_light_mats):
        light_mats[i][k_cur] = m
        light_powers[i][k_cur] = light_params[i]["power"]
    cam_mats[k_cur] = _orthonormal(_matrix(cam_obj.matrix_world))
    cam_names[k_cur] = cam_obj.name
    deforming: list[str] = []
    if n_f > 1:
        mesh_pos = {k: i for i, k in enumerate(mesh_keys)}
        light_pos = {k: i for i, k in enumerate(light_keys)}
        probe_by_name = {v[0]: (i, v) for i, v in deform_probe.items()}
        try:
            for k, f in enumerate(frames):
                if f == current:
                    continue
                frame_set(f)
                for inst in depsgraph.object_instances:
                    ob = inst.object
                    if ob.type == "LIGHT":
                        i = light_pos.get(_instance_key(inst))
                        if i is None:
                            warn(f"light {ob.name!r} is not there at frame {current}; not rendered")
                            continue
                        m = _matrix(inst.matrix_world)
                        light_mats[i][k] = m
                        p = _light_params(ob.data, np.linalg.norm(m[:3, :3], axis=0), lambda _m: None, ob.name)
                        light_powers[i][k] = p["power"]
                    elif ob.type in GEOMETRY_TYPES:
                        i = mesh_pos.get(_instance_key(inst))
                        if i is None:
                            continue
                        mesh_mats[i][k] = _matrix(inst.matrix_world)
                        probe = probe_by_name.get(ob.name)
                        if probe is not None and ob.name not in deforming and _deformed(ob, probe[1]):
                            deforming.append(ob.name)
                cam = camera if camera is not None else depsgraph.scene.camera
                if cam is not None:
                    cam_mats[k] = _orthonormal(_matrix(cam.matrix_world))
                    cam_names[k] = cam.name
        finally:
            frame_set(current)
    for seq in (*mesh_mats, *light_mats, cam_mats, cam_names):
        _fill_gaps(seq)

    # ---- assemble
    sc = restircl.Scene(name=scene.name, frame_count=n_f)
    sc.materials = materials
    for (name, verts, tris, ids), mats in zip(mesh_records, mesh_mats, strict=True):
        sc.meshes.append(restircl.Mesh(name=name, vertices=verts, triangles=tris, material_ids=ids,
                                       transforms=_transforms(mats)))
    light_fields = set(getattr(restircl.Light, "__dataclass_fields__", {}))
    soft_lights = []
    for params, mats, powers in zip(light_params, light_mats, light_powers, strict=True):
        params = dict(params)
        soft = params.pop("soft_falloff", None)
        if soft is not None and "soft_falloff" in light_fields:
            params["soft_falloff"] = soft
        elif soft:
            soft_lights.append(params["name"])
        p = np.asarray(powers, dtype=np.float64)
        if len(p) > 1 and not np.all(p == p[0]):
            peak = float(np.max(np.abs(p)))
            params["power"] = peak
            params["power_per_frame"] = p / peak if peak > 0 else np.zeros_like(p)
        sc.lights.append(restircl.Light(transforms=_transforms(mats), **params))
    if soft_lights:
        warn(f"light(s) {', '.join(repr(n) for n in soft_lights[:5])}: 'Soft Falloff' is rendered as a "
             "physical sphere light (turn Soft Falloff off to match Cycles near the light)")
    if deforming:
        warn(f"object(s) {', '.join(repr(n) for n in deforming[:5])} deform during the animation: the "
             "geometry is exported again each frame and the reuse history starts over")
    cuts = tuple(i for i in range(1, n_f) if cam_names[i] != cam_names[i - 1])
    sc.camera = restircl.Camera(transforms=_transforms(cam_mats), cuts=cuts, **cam_params)
    _world_warning(scene, warn)
    stats = {
        "objects": len(mesh_records), "instances": n_instances, "triangles": sc.triangle_count,
        "lights": len(sc.lights), "materials": len(materials),
        "emissive_materials": sum(1 for m in materials if m.is_emissive),
    }
    if not sc.meshes and not sc.lights:
        warn("the scene is empty: nothing to render")
    elif not sc.lights and not stats["emissive_materials"]:
        warn("the scene has no lights and no emissive materials: the image is black")
    return Export(scene=sc, frames=frames, warnings=warnings, stats=stats, deforming=deforming)


def _fill_gaps(seq: list) -> None:
    """Frames where an object was absent take the nearest earlier (else later) frame's value."""
    known = [i for i, v in enumerate(seq) if v is not None]
    for i in range(len(seq)):
        if seq[i] is None:
            earlier = [j for j in known if j < i]
            seq[i] = seq[earlier[-1] if earlier else known[0]]


def _transforms(mats: list[np.ndarray]) -> np.ndarray:
    return mats[0] if _all_equal(mats) else np.stack(mats)


def _digest(arr: np.ndarray) -> bytes:
    return hashlib.blake2b(np.ascontiguousarray(arr, dtype=np.float32).tobytes(), digest_size=16).digest()


def _may_deform(ob) -> bool:
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


def _deformed(ob, probe: tuple[str, int, bytes]) -> bool:
    geo = _read_geometry(ob)
    if geo is None:
        return probe[1] != 0
    return len(geo.vertices) != probe[1] or _digest(geo.vertices) != probe[2]


def _all_equal(mats: list[np.ndarray]) -> bool:
    first = mats[0]
    return all(np.array_equal(m, first, equal_nan=True) for m in mats[1:])


def _world_warning(scene, warn: Callable[[str], None]) -> None:
    world = scene.world
    if world is None:
        return
    if world.node_tree is None:
        if any(c > 0 for c in world.color):
            warn("world lighting is not rendered (direct light from lights and emissive objects only)")
        return
    for node in world.node_tree.nodes:
        if node.bl_idname == "ShaderNodeBackground":
            col, strength = node.inputs["Color"], node.inputs["Strength"]
            lit = col.is_linked or strength.is_linked or (
                strength.default_value > 0 and any(c > 0 for c in col.default_value[:3]))
            if lit:
                warn("world lighting is not rendered (direct light from lights and emissive objects only)")
            return
