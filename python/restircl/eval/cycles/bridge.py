"""Cycles beside restircl in `restircl report`: a restircl Scene written into a bpy scene, a .blend read into a
restircl Scene (through the add-on's exporter), and time-limited Cycles renders with direct light only.

Needs the `bpy` module (pip install bpy, Blender as a Python module); `available()` says whether it imports.
Cycles is set up as in the Blender agreement tests (tests/blender/test_blender_cycles.py, docs/units.md): every bounce
limit 0, light threshold 0, no adaptive sampling, no denoising, no clamping, box pixel filter of width 1, the
scene's Environment as the world (eval/cycles/world.py; black without one), light objects seen by camera rays as each
Light.visible_camera says (restircl draws them as Cycles does).
"""

from __future__ import annotations

import re
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...scene.scene import Scene
from .alpha import apply_alpha, write_uvs
from .linking import linking_to_bpy
from .materials import is_plain_diffuse, material_to_bpy
from .world import world_to_bpy


def available() -> bool:
    try:
        import bpy  # noqa: F401
    except ImportError:
        return False
    return True


def _bpy():
    import bpy

    return bpy


# ---- restircl Scene -> bpy scene ------------------------------------------------------------------------


def _matrix(m: np.ndarray):
    from mathutils import Matrix

    return Matrix([list(map(float, row)) for row in np.asarray(m, dtype=np.float64)])


def black_world(bpy, sc) -> None:
    """A new world that emits nothing, and the Standard view transform (no tone mapping) for scene sc."""
    world = bpy.data.worlds.new("World")
    sc.world = world
    if world.node_tree is None:
        world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    if bg is not None:
        bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
        bg.inputs["Strength"].default_value = 0.0
    sc.view_settings.view_transform = "Standard"


def node_material(bpy, name: str):
    """A new material with an empty node tree but for its output node: (material, tree, output node)."""
    m = bpy.data.materials.new(name)
    tree = m.node_tree
    if tree is None:  # Blender < 5: node trees are opt-in
        m.use_nodes = True
        tree = m.node_tree
    tree.nodes.clear()
    return m, tree, tree.nodes.new("ShaderNodeOutputMaterial")


def _material(bpy, mat):
    """A Diffuse BSDF (roughness 0) of the albedo, plus an Emission shader (two-sided, as restircl's) if any."""
    m, tree, out = node_material(bpy, mat.name)
    shaders = []
    if any(c > 0 for c in mat.albedo) or not mat.is_emissive:
        d = tree.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (*map(float, mat.albedo), 1.0)
        d.inputs["Roughness"].default_value = 0.0
        shaders.append(d)
    if mat.is_emissive:
        e = tree.nodes.new("ShaderNodeEmission")
        e.inputs["Color"].default_value = (*map(float, mat.emission), 1.0)
        e.inputs["Strength"].default_value = float(mat.emission_strength)
        shaders.append(e)
    if len(shaders) == 2:
        add = tree.nodes.new("ShaderNodeAddShader")
        tree.links.new(shaders[0].outputs[0], add.inputs[0])
        tree.links.new(shaders[1].outputs[0], add.inputs[1])
        tree.links.new(add.outputs[0], out.inputs["Surface"])
    else:
        tree.links.new(shaders[0].outputs[0], out.inputs["Surface"])
    return m


def to_bpy(scene: Scene, frame: int = 0):
    """Replace Blender's data with `scene` at `frame` (factory settings, empty) and return the bpy scene.
    Geometry, lights and camera are written in world space at that frame (no animation)."""
    bpy = _bpy()
    scene.validate()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    cam = scene.camera
    assert cam is not None
    sc.render.resolution_x, sc.render.resolution_y = int(cam.width), int(cam.height)
    sc.render.resolution_percentage = 100
    black_world(bpy, sc)
    if scene.environment is not None:
        world_to_bpy(bpy, sc, scene.environment)
    mats = [_material(bpy, m) if is_plain_diffuse(m) else material_to_bpy(bpy, m, node_material)
            for m in scene.materials]
    for bmat, m in zip(mats, scene.materials, strict=True):
        apply_alpha(bpy, bmat, m)
    for mesh in scene.meshes:
        if len(mesh.triangles) == 0:
            continue
        m = Scene.at(mesh.transforms, frame)
        verts = mesh.vertices @ m[:3, :3].T + m[:3, 3]
        me = bpy.data.meshes.new(mesh.name)
        me.from_pydata(verts.tolist(), [], mesh.triangles.tolist())
        write_uvs(me, mesh)
        used, local = np.unique(mesh.material_ids, return_inverse=True)
        for i in used:
            me.materials.append(mats[int(i)])
        me.polygons.foreach_set("material_index", local.astype(np.int32))
        me.update()
        sc.collection.objects.link(bpy.data.objects.new(mesh.name, me))
    for lt in scene.lights:
        kind = {"point": "POINT", "spot": "SPOT", "sun": "SUN", "area": "AREA"}[lt.type]
        ld = bpy.data.lights.new(lt.name, kind)
        ld.color = tuple(map(float, lt.color))
        ld.energy = lt.power_at(frame)
        if kind in ("POINT", "SPOT"):
            ld.shadow_soft_size = float(lt.radius)
            ld.use_soft_falloff = bool(lt.soft_falloff)
        if kind == "SPOT":
            ld.spot_size = float(lt.spot_size)
            ld.spot_blend = float(lt.spot_blend)
        if kind == "SUN":
            ld.angle = float(lt.angle)
        if kind == "AREA":
            ld.shape = lt.shape
            ld.size = float(lt.size)
            ld.size_y = float(lt.size_y)
        ob = bpy.data.objects.new(lt.name, ld)
        sc.collection.objects.link(ob)
        ob.matrix_world = _matrix(Scene.at(lt.transforms, frame))
        ob.visible_camera = bool(lt.visible_camera)
    cd = bpy.data.cameras.new("Camera")
    cd.lens = float(cam.lens)
    cd.sensor_width, cd.sensor_height = float(cam.sensor_width), float(cam.sensor_height)
    cd.sensor_fit = cam.sensor_fit
    cd.shift_x, cd.shift_y = float(cam.shift_x), float(cam.shift_y)
    cd.type, cd.ortho_scale = cam.type, float(cam.ortho_scale)
    cd.clip_start, cd.clip_end = 1e-3, 1e5
    if cam.has_dof:  # the thin lens in Blender's terms (the inverse of the add-on's export/camera.py)
        cd.dof.use_dof, cd.dof.focus_distance = True, cam.focus_at(frame)
        cd.dof.aperture_fstop = (1.0 if cam.type == "ORTHO" else cam.lens * 1e-3) / (2.0 * cam.aperture_radius)
        cd.dof.aperture_blades, cd.dof.aperture_rotation = int(cam.aperture_blades), float(cam.aperture_rotation)
        cd.dof.aperture_ratio = float(cam.aperture_ratio)
    ob = bpy.data.objects.new("Camera", cd)
    sc.collection.objects.link(ob)
    ob.matrix_world = _matrix(Scene.at(cam.transforms, frame))
    sc.camera = ob
    linking_to_bpy(bpy, [(lt.name, lt.linking) for lt in scene.lights] + [(m.name, m.linking) for m in scene.meshes])
    bpy.context.view_layer.update()
    return sc


# ---- .blend -> restircl Scene -----------------------------------------------------------------------------


def _addon():
    from ...io.blend import addon_module

    return addon_module()


def load_blend(path: str | Path, width: int | None = None, height: int | None = None, frame: int | None = None,
               all_frames: bool = False):
    """Open a .blend, set the resolution if given, export the scene at `frame` (default: its current frame; with
    all_frames, from frame_start with the motion of the whole frame range) with the restircl add-on's exporter.
    Returns (restircl Scene, bpy scene, exporter warnings)."""
    from ...io.blend import open_blend

    bpy = _bpy()
    export = _addon().export
    sc = open_blend(path, width, height)
    if all_frames:
        frame = int(sc.frame_start)
    if frame is not None:
        sc.frame_set(int(frame))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    frames = (list(range(int(sc.frame_start), int(sc.frame_end) + 1, max(int(sc.frame_step), 1))) if all_frames
              else [int(sc.frame_current)])
    exp = export.export_scene(depsgraph, frames, frame_set=sc.frame_set)
    out = exp.scene
    out.name = Path(path).stem
    return out, sc, list(exp.warnings)


# ---- Cycles renders ----------------------------------------------------------------------------------------


def direct_only(sc, samples: int, seed: int = 0, threads: int = 0, time_limit: float = 0.0) -> None:
    """Cycles settings of the agreement tests: direct light only, box filter 1 px, nothing that biases."""
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.device = "CPU"
    c.samples = int(samples)
    c.seed = int(seed)
    c.use_animated_seed = False
    for name in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces",
                 "transparent_max_bounces"):
        setattr(c, name, 0)
    c.light_sampling_threshold = 0.0
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.time_limit = float(time_limit)
    if threads:
        sc.render.threads_mode = "FIXED"
        sc.render.threads = int(threads)
    else:
        sc.render.threads_mode = "AUTO"


def light_paths(sc, settings) -> None:
    """Cycles' Light Paths of bpy scene sc set to restircl `settings`' (max_bounces, diffuse, glossy, transmission,
    min light bounces, clamp direct and indirect, light threshold), after direct_only: the same bounces on both
    sides. Volume bounces stay 0 (restircl has none yet). Cycles counts a ray passing through a light as a
    transparent bounce and ends the path at the limit; restircl's lights never stop a ray, so the limit is set past
    any path."""
    c = sc.cycles
    c.transparent_max_bounces = 1024
    c.blur_glossy = 0.0  # Filter Glossy blurs glossy lobes after the first bounce: a bias restircl does not add
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.max_bounces = int(settings.max_bounces)
    c.diffuse_bounces = int(settings.diffuse_bounces)
    c.glossy_bounces = int(settings.glossy_bounces)
    c.transmission_bounces = int(settings.transmission_bounces)
    c.min_light_bounces = int(settings.min_light_bounces)
    c.sample_clamp_direct = float(settings.clamp_direct)
    c.sample_clamp_indirect = float(settings.clamp_indirect)
    c.light_sampling_threshold = float(settings.light_threshold)


_TIME = re.compile(r"^(?:(\d+):)?(\d+):(\d+(?:\.\d+)?)$")


def parse_time(text: str) -> float | None:
    """Blender's 'MM:SS.ff' or 'HH:MM:SS.ff' as seconds."""
    m = _TIME.match(text.strip())
    if not m:
        return None
    h, mnt, s = m.groups()
    return int(h or 0) * 3600 + int(mnt) * 60 + float(s)


@dataclass
class CyclesResult:
    image: np.ndarray  # (H, W, 3) float32, rows top first
    render_seconds: float  # Cycles' render time (without synchronisation), from the EXR metadata
    total_seconds: float  # wall clock of the whole render call (sync, render, writing the file)
    samples: int | None  # samples per pixel when fixed (None when the time limit decided)


def _read_exr(path: Path) -> tuple[np.ndarray, dict]:
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as f:
        header = {}
        chans: dict[str, np.ndarray] = {}
        for part in f.parts:
            header.update({k: v for k, v in part.header.items() if isinstance(v, str)})
            for name, ch in part.channels.items():
                chans[name] = np.asarray(ch.pixels, dtype=np.float32)
    rgb = []
    for c in "RGB":
        key = next((k for k in chans if k == c or k.endswith("Combined." + c)), None)
        if key is None:
            raise RuntimeError(f"no {c} channel in {path}: {sorted(chans)}")
        rgb.append(chans[key])
    return np.stack(rgb, axis=-1), header


def exr_output(sc, multilayer: bool = False) -> None:
    """Blender writes the render as a 32-bit float EXR: the Combined pass, or with `multilayer` every pass on."""
    im = sc.render.image_settings
    if hasattr(im, "media_type"):
        im.media_type = "MULTI_LAYER_IMAGE" if multilayer else "IMAGE"
    im.file_format = "OPEN_EXR_MULTILAYER" if multilayer else "OPEN_EXR"
    im.color_depth = "32"
    im.exr_codec = "ZIP"


def render(sc, seconds: float | None = None, samples: int | None = None, seed: int = 0, threads: int = 0,
           workdir: Path | None = None, paths=None, adjust: Callable[[object], None] | None = None) -> CyclesResult:
    """Render the bpy scene `sc` with Cycles, direct light only, or with the Light Paths of restircl Settings
    `paths`: until `seconds` of render time (Cycles' time_limit, samples unbounded) or for a fixed number of
    `samples`. `adjust(sc)` changes the settings last (a test's variant of them)."""
    bpy = _bpy()
    if (seconds is None) == (samples is None):
        raise ValueError("give exactly one of seconds and samples")
    direct_only(sc, samples=samples or 1 << 24, seed=seed, threads=threads, time_limit=seconds or 0.0)
    if paths is not None:
        light_paths(sc, paths)
    if adjust is not None:
        adjust(sc)
    exr_output(sc)
    sc.render.use_stamp_render_time = True
    tmp = tempfile.TemporaryDirectory(dir=workdir)
    try:
        path = Path(tmp.name) / "cycles.exr"
        sc.render.filepath = str(path)
        t0 = time.perf_counter()
        bpy.ops.render.render(write_still=True, scene=sc.name)
        total = time.perf_counter() - t0
        img, header = _read_exr(path)
    finally:
        tmp.cleanup()
    render_s = None
    for key, value in header.items():
        if key.startswith("cycles.") and key.endswith(".render_time"):
            render_s = parse_time(value)
    if render_s is None:
        render_s = seconds if seconds is not None else total
    return CyclesResult(img, float(render_s), total, samples)


def scene_for(scene: Scene | None, blend: str | Path | None = None, width: int | None = None,
              height: int | None = None):
    """(restircl Scene, bpy scene): from a .blend through the exporter, or a restircl Scene written to bpy."""
    if blend is not None:
        out, sc, _ = load_blend(blend, width, height)
        return out, sc
    assert scene is not None
    return scene, to_bpy(scene)


__all__ = ["CyclesResult", "available", "direct_only", "exr_output", "load_blend", "parse_time", "render", "scene_for",
           "to_bpy"]
