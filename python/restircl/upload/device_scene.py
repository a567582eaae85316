"""The scene as the device holds it: geometry (BVH and triangles), materials, lights, the light array and the
per-object motion rows, uploaded when the frame's scene differs from what the device holds, with the bookkeeping
of how the lights changed (what the ReSTIR history may keep)."""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np
import pyopencl as cl

from ..bvh.build import build_bvh, make_tris
from ..bvh.packets import device_arrays
from ..core import layouts as L
from ..core.buffers import upload, upload_parts
from ..lights.array import LightArray, build_light_array
from ..lights.camera_visible import camera_light_indices, camera_light_table
from ..lights.device_lights import DeviceLights, scene_lights
from ..lights.hit import analytic_light_count, triangle_lights
from ..lights.linking import object_bits
from ..lights.tree import LightTree, build_light_tree
from ..scene.scene import Scene
from .alpha import scene_has_records, with_transparency
from .attributes import attribute_rows
from .deform_motion import deform_motion
from .glass_tables import device_tables
from .materials import pack_materials
from .textures import LoadedImage, PackedTextures, TexturePacker, warn_missing_uv_maps, warn_textured_emission
from .thin_wall_shadow import scene_has_thin_shadow
from .tri_attributes import needs_attributes, object_infos, tri_attributes


def lights_switched(old: np.ndarray, new: np.ndarray, ratio: float) -> bool:
    """Did any light switch on or off, or change its power by more than `ratio`?"""
    if ratio == 0 or len(old) != len(new):
        return False
    on_old, on_new = old > 0, new > 0
    if np.any(on_old != on_new):
        return True
    both = on_old & on_new
    r = new[both] / old[both]
    return bool(np.any((r > ratio) | (r < 1.0 / ratio)))


class DeviceScene:
    """Device buffers of a Scene at one frame of its animation (upload(frame) moves them to another frame)."""

    def __init__(self, context: cl.Context, scene: Scene, slots_per_light: float, light_change_ratio: float,
                 area_sampling: str = "area", environment_table: str | None = None) -> None:
        self.context = context
        self.scene = scene
        self.slots_per_light = slots_per_light
        self.area_sampling = area_sampling
        self.environment_table = environment_table  # None: lights/environment.py's default for the map's size
        self.light_change_ratio = light_change_ratio
        # what moves, decided once: each scans every light, ~50 ms per frame at 1e5 explicit lights when asked
        # every frame
        self.moving_objects = scene.has_moving_objects
        self.moving_lights = scene.has_moving_lights
        self.frame_count = scene.frames
        self._geometry_key: int | None = None
        self._lights_key: int | None = None
        self.lights: DeviceLights
        self.light_array: LightArray
        self.tree_wanted = False  # the samplers draw from the light tree: build it with every light upload
        self.light_tree: LightTree | None = None
        self.tree_seconds = 0.0  # the last tree build's time
        self._no_tree: cl.Buffer | None = None  # the placeholder of the tree arguments without a tree
        self.motion_buf: cl.Buffer | None = None
        self.camera_lights = camera_light_indices(scene)  # the lights camera rays test (scene light indices)
        self.camera_lights_buf: cl.Buffer | None = None
        self.ggx_tables_buf: cl.Buffer | None = None  # glossy builds only (upload_ggx_tables)
        self._textures: PackedTextures | None = None  # packed once: materials do not animate (texels not kept)
        self._images: dict[tuple, LoadedImage] = {}  # the images on the device by image_key (their mip chains)
        self.textures: dict[str, cl.Buffer] = {}  # the texture programs, image table and texels by parameter name
        self._frame = 0  # the frame of the geometry on the device
        self.lights_changed = True  # this frame's light records differ from (or may differ from) the last frame's
        self.light_indices_changed = False  # the light count changed: old reservoirs point at other lights
        self.lights_switched = False  # a light switched on or off, or its power jumped (light_change_ratio)
        self.edited = False  # this frame shows an interactive edit (edit()): something moved since the last
        self._pending_edit = False
        self._edit_motion: dict[int, np.ndarray] | None = None  # mesh index -> its transform before the edit
        self._edit_rows_on_device = False  # the motion rows on the device are an edit's, not identities
        # counts, for tests and tools; "textures" is the image table and its texels
        self.uploads: dict[str, int] = {"geometry": 0, "lights": 0, "materials": 0, "textures": 0}

    def upload(self, frame: int, last_frame: int | None) -> None:
        """Upload geometry and lights for `frame` when they differ from what the device holds; `last_frame` is the
        frame rendered before (the motion rows reproject to it)."""
        scene = self.scene
        self.light_indices_changed = self.lights_switched = False
        self.edited, self._pending_edit = self._pending_edit, False
        geo_key = frame if self.moving_objects else 0
        world = None
        if self._geometry_key != geo_key:
            self._frame = frame
            world = scene.world_triangles(frame)
            self._upload_geometry(world)
            self._geometry_key = geo_key
        lights_key = frame if (self.moving_lights or self.moving_objects) else 0
        self.lights_changed = self._lights_key != lights_key
        if self.lights_changed:
            if world is None:
                world = scene.world_triangles(frame)
            self._upload_lights(scene_lights(scene, frame, world, self.area_sampling, self.environment_table))
            self._lights_key = lights_key
        if world is not None:  # the geometry or the lights changed: the triangle -> light map of BSDF rays
            self.tri_light_buf = upload(self.context, triangle_lights(self._leaf_order, self.lights))
            self.analytic_lights = analytic_light_count(self.lights)
            self.triangle_lights = bool(np.any(self.lights.source < 0))
        edit_rows = self._edit_motion is not None
        if self.moving_objects or self.motion_buf is None or edit_rows or self._edit_rows_on_device:
            self.motion_buf = upload(self.context, self._motion_rows(frame, last_frame, self._edit_motion))
            self._edit_rows_on_device, self._edit_motion = edit_rows, None
        if self.moving_lights or self.camera_lights_buf is None:
            prev_f = last_frame if last_frame is not None else frame
            table = camera_light_table(scene, self.camera_lights, self.lights.source, frame, prev_f,
                                       min(frame + 1, self.frame_count - 1))
            self.camera_lights_buf = upload(self.context, table)

    def edit(self, *, geometry: bool = False, lights: bool = False, materials: bool = False,
             moved: dict[int, np.ndarray] | None = None) -> None:
        """The Scene was edited in place (an interactive session): the next upload() re-uploads what changed and
        only that. geometry: some mesh's vertices or triangles; lights: some light's record; materials: some
        material (its records and texture programs go up again, the texels only when an image differs); moved:
        mesh index -> its transform before the edit, so that the next frame's motion rows reproject the moved
        objects' history (compiled in by Renderer(interactive=True))."""
        if materials:
            self._textures = None
            transparent = self.material_flags.get("HAS_TRANSPARENCY", False)
            self._upload_materials()
            # coverage records live in the Tri array (upload/alpha.py): it goes up again where some coverage may have
            # changed
            geometry = geometry or transparent or self.material_flags["HAS_TRANSPARENCY"]
        if geometry or moved:
            self._geometry_key = None
        emissive = {i for i, m in enumerate(self.scene.materials) if m.is_emissive}
        if geometry or any(emissive.intersection(np.unique(self.scene.meshes[k].material_ids).tolist())
                           for k in moved or {}):
            self._lights_key = None  # emissive triangles are lights
        if lights:
            self._lights_key = None
            self.camera_lights_buf = None  # what the camera sees of the lights moves with them
        if moved:
            self._edit_motion = dict(moved)
        self._pending_edit = True

    def _upload_geometry(self, world) -> None:
        self.uploads["geometry"] += 1
        t0 = time.perf_counter()
        bvh = build_bvh(world.v0, world.v1, world.v2)
        self._leaf_order = bvh.order
        tris = make_tris(world.v0, world.v1, world.v2, world.material, world.prim, bvh.order)
        tris["e2"][:, 3] = L.int_bits(object_bits(self.scene, world.object[bvh.order]))
        self.bvh_seconds = time.perf_counter() - t0
        nodes, tris_dev = device_arrays(bvh.nodes, tris)
        tris_dev = with_transparency(self.scene, tris_dev, world, bvh.order)
        self.nodes_buf = upload(self.context, nodes)
        self.tris_buf = upload(self.context, tris_dev)
        self.triangle_count = len(world)
        self._upload_materials()
        attributes = needs_attributes(self.scene, self.material_flags["HAS_TEXTURES"])
        self.objects_buf = upload(self.context, object_infos(self.scene, attributes))
        attr = tri_attributes(self.scene, world, bvh.order, self._frame) if attributes else np.zeros(0, np.uint8)
        self._tri_attr_names = self._attribute_names
        rows = attribute_rows(self.scene, world, bvh.order, self._tri_attr_names, attr) if attributes else attr
        if len(rows):  # the corner colours of the Attribute nodes follow the records
            attr = np.concatenate([attr.view(np.float32).reshape(-1, 4), rows])
        self.tri_attr_buf = upload(self.context, attr)  # 16 zero bytes, never read, without attributes

    def _upload_materials(self) -> None:
        if self._textures is not None:
            return
        # images the device holds are not read again, and their texels go up only when the image table differs
        packer = TexturePacker(self.scene.materials, self._images)
        self._attribute_names = packer.attribute_names
        if getattr(self, "_tri_attr_names", packer.attribute_names) != packer.attribute_names:
            self._geometry_key = None  # an edit names other attributes: their colours go up with the geometry
        warn_missing_uv_maps(self.scene.meshes, self.scene.materials)
        warn_textured_emission(self.scene.meshes, self.scene.materials)
        packed = pack_materials(self.scene.materials, packer.index)
        self.uploads["materials"] += 1
        same_images = bool(self.textures) and packer.image_keys == list(self._images)
        tex = packer.packed(texels=not same_images)
        self.nonfinite_texels = tex.nonfinite_texels
        thin_shadow = scene_has_thin_shadow(self.scene)  # its shadow rays take the transparent ones' loop
        self.material_flags = {"HAS_GLOSSY": packed.glossy or packed.transmission, "HAS_TEXTURES": packed.textured,
                               "HAS_TRANSMISSION": packed.transmission, "HAS_THIN_FILM": packed.thin_film,
                               "HAS_TRANSPARENCY": scene_has_records(self.scene),
                               "HAS_THIN_SHADOW": thin_shadow}
        self.materials_buf = upload(self.context, packed.materials)
        self.closures_buf = upload(self.context, packed.closures)
        if same_images:
            self.textures["tex_nodes"] = upload(self.context, tex.nodes)
        else:
            self.uploads["textures"] += 1
            self.textures = {"tex_nodes": upload(self.context, tex.nodes),
                             "tex_images": upload(self.context, tex.images), "texels": upload(self.context, tex.texels)}
        self._images = packer.images
        self._textures = replace(tex, texels=tex.texels[:0])  # the device has them; the mip chains are in _images
        if packed.glossy:
            self.upload_ggx_tables()

    def upload_ggx_tables(self) -> None:
        """The GGX and glass energy tables the BSDF resolve (primary pass) reads in glossy builds (shipped with the
        package: upload/ggx_tables.py, upload/glass_tables.py); diffuse-only scenes leave them out."""
        if self.ggx_tables_buf is None:
            self.ggx_tables_buf = upload(self.context, device_tables())

    def _upload_lights(self, lights: DeviceLights) -> None:
        self.uploads["lights"] += 1
        old = getattr(self, "lights", None)
        if old is not None and len(old) != len(lights):
            self.light_indices_changed = True
        elif old is not None:
            self.lights_switched = lights_switched(old.power, lights.power, self.light_change_ratio)
        self.lights = lights
        self.light_array = build_light_array(lights.power, self.slots_per_light)
        self.lights_buf = upload_parts(self.context, lights.device_parts())
        self.slots_buf = upload(self.context, self.light_array.slots)
        self.light_pdf_buf = upload(self.context, self.light_array.pdf)
        self.light_tree = None
        if self.tree_wanted:
            self._upload_light_tree()

    def use_light_tree(self) -> None:
        """Build the light tree (lights/tree.py) now and again whenever the lights change."""
        self.tree_wanted = True
        if self.light_tree is None:
            self._upload_light_tree()

    def _upload_light_tree(self) -> None:
        t0 = time.perf_counter()
        lights = self.lights
        self.light_tree = tree = build_light_tree(lights.records, lights.types, lights.power,
                                                        self.light_array.pdf)
        self.tree_seconds = time.perf_counter() - t0
        self.tree_bufs = {"tree_nodes": upload(self.context, tree.nodes),
                          "tree_info": upload(self.context, tree.light_info),
                          "tree_distant": upload(self.context, tree.distant)}

    def _motion_rows(self, frame: int, last_frame: int | None, moved: dict[int, np.ndarray] | None = None
                     ) -> np.ndarray:
        """Per object: rows of M_prev M_cur^-1 (reprojection), then of M_next M_cur^-1 (the Vector pass);
        identities (uploaded once) when nothing moves. `moved` gives M_prev of objects an edit moved."""
        scene = self.scene
        motion = np.zeros((max(len(scene.meshes), 1), 2, 3, 4), np.float32)
        motion[:, :, :, :3] = np.eye(3)
        if self.moving_objects:
            prev_f = last_frame if last_frame is not None else frame
            next_f = min(frame + 1, self.frame_count - 1)
            for k, mesh in enumerate(scene.meshes):
                if mesh.deforms:
                    motion[k] = deform_motion(mesh, frame, prev_f), deform_motion(mesh, frame, next_f)
                    continue
                inv = np.linalg.inv(Scene.at(mesh.transforms, frame))
                motion[k, 0] = (Scene.at(mesh.transforms, prev_f) @ inv)[:3, :]
                motion[k, 1] = (Scene.at(mesh.transforms, next_f) @ inv)[:3, :]
        for k, prev in (moved or {}).items():
            motion[k, 0] = (prev @ np.linalg.inv(Scene.at(scene.meshes[k].transforms, frame)))[:3, :]
        return motion

    @property
    def sampled_light_count(self) -> int:
        """The number of lights the samplers draw from: 0 when no light emits (an empty light array)."""
        return len(self.lights) if self.light_array.slot_count and len(self.light_array.slots) else 0

    @property
    def geometry(self) -> dict[str, cl.Buffer]:
        """The kernels' geometry arguments (BVH nodes and triangles), by parameter name."""
        return {"nodes": self.nodes_buf, "tris": self.tris_buf}

    @property
    def surface(self) -> dict[str, cl.Buffer]:
        """What the primary pass reads about surfaces beyond the triangles: materials and their closures, the
        per-triangle attributes and per-object texture spaces, the texture programs and texels, by parameter name."""
        return {"materials": self.materials_buf, "closures": self.closures_buf, "tri_attr": self.tri_attr_buf,
                "objects": self.objects_buf, **self.textures}

    @property
    def light_tree_args(self) -> dict[str, cl.Buffer]:
        """The light tree's buffers by the RIS kernels' parameter names (placeholders when there is no tree)."""
        if self.light_tree is None:
            if self._no_tree is None:
                self._no_tree = upload(self.context, np.zeros(16, np.uint8))
            return dict.fromkeys(("tree_nodes", "tree_info", "tree_distant"), self._no_tree)
        return self.tree_bufs

    @property
    def light_sampling(self) -> dict[str, cl.Buffer]:
        """The light records and the light array, by the samplers' parameter names."""
        return {"lights": self.lights_buf, "slots": self.slots_buf, "light_pdf": self.light_pdf_buf}
