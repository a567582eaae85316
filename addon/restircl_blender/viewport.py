"""RenderEngine.view_update / view_draw: the Rendered shading mode of the 3D view, on a ViewportSession.

Both run on Blender's main thread and are the only places here that touch bpy: view_update exports the scene
(the first time, or again when a setting changed) and turns depsgraph updates into scene edits; view_draw reads
the view from region_data, hands it to the session and draws the newest frame. The worker thread never sees bpy.
Nothing lets an exception escape into Blender: failures go to the header's status text.
"""

from __future__ import annotations

import traceback
from dataclasses import dataclass, field

from . import export
from .export.convert import matrix
from .properties import make_settings
from .viewport_edit import SceneEdit
from .viewport_lens import view_lens
from .viewport_session import ViewportSession, scaled_size, view_camera


@dataclass
class Viewport:
    """What a RenderEngine instance keeps for its 3D view."""

    session: ViewportSession | None
    settings_key: tuple
    mesh_names: frozenset  # mesh objects exported once each: their transform edits need no re-export
    message: str = ""  # why there is no session
    material_reads: list = field(default_factory=list)  # the last export's: materials re-read alone in this order
    texture: object | None = None  # the GPU texture of frame `texture_index`
    texture_index: int = -1


def free(engine) -> None:
    """Stop the worker (RenderEngine.free / __del__, and before a new session)."""
    try:
        vp = getattr(engine, "viewport", None)
        engine.viewport = None
    except ReferenceError:  # __del__ of an engine whose Blender data is gone
        return
    if vp is not None and vp.session is not None:
        vp.session.stop()


def _settings_key(props) -> tuple:
    return (tuple(sorted(props.settings_kwargs().items())), props.device.strip(), int(props.viewport_samples))


def view_update(engine, context, depsgraph) -> None:
    """RenderEngine.view_update: never raises."""
    try:
        _view_update(engine, depsgraph)
    except Exception as exc:  # a bug of ours: show it, never crash Blender
        traceback.print_exc()
        free(engine)
        engine.viewport = Viewport(None, (), frozenset(), f"unexpected {type(exc).__name__}: {exc}")


def _view_update(engine, depsgraph) -> None:
    import restircl

    props = depsgraph.scene.restircl
    key = _settings_key(props)
    vp = getattr(engine, "viewport", None)
    if vp is not None and vp.session is not None and vp.settings_key == key and vp.session.error is None:
        edit = scene_edit(depsgraph, vp)
        if edit is not None:
            vp.session.edit(edit)
        return
    free(engine)
    known = (restircl.SceneError, restircl.SettingError, restircl.DeviceError, export.ExportError)
    try:
        exp = export.export_scene(depsgraph, None)
        exp.scene.validate()
        settings = make_settings(restircl, props)
    except known as exc:
        engine.viewport = Viewport(None, key, frozenset(), str(exc))
        return
    session = ViewportSession(exp.scene, settings, device=props.device.strip() or None,
                              samples=int(props.viewport_samples))
    engine.viewport = Viewport(session.start(), key, unique_mesh_names(exp.scene),
                               material_reads=exp.material_reads)


def unique_mesh_names(scene) -> frozenset:
    names = [m.name for m in scene.meshes]
    return frozenset(n for n in names if names.count(n) == 1)


def scene_edit(depsgraph, vp: Viewport) -> SceneEdit | None:
    """The scene edit that depsgraph.updates describe: a moved mesh object by its new matrix alone; lights (a
    light object or its data) by re-reading the lights alone; materials (a material, a node group, an image) by
    re-reading the materials alone; anything else (geometry, the world, objects added or removed) by a re-export
    that the session compares with its scene (and that `vp` takes its mesh names and material order from). None
    when nothing that is rendered changed (the camera's own updates: the view comes from the 3D view)."""
    import bpy

    transforms = {}
    full = lights = materials = False
    shading = trees = False  # an object's shading or a node tree changed: a material edit's echo, or something else
    mats = None
    updates = list(depsgraph.updates)
    # Blender 5.3 flags an object's geometry as updated when only one of its materials changed (a material can
    # displace); its mesh data's own update then says the geometry is the same
    material_edit = any(isinstance(u.id, bpy.types.Material) for u in updates)
    reshaped = {u.id.name for u in updates if isinstance(u.id, bpy.types.Mesh) and u.is_updated_geometry}
    for u in updates:
        idb = u.id
        if isinstance(idb, bpy.types.Object):
            if idb.type == "CAMERA":
                continue
            if idb.type == "LIGHT":
                lights = True
                continue
            echo = (material_edit and u.is_updated_geometry and idb.type == "MESH"
                    and getattr(idb.data, "name", None) not in reshaped)
            if u.is_updated_shading and (echo or not u.is_updated_geometry) and not u.is_updated_transform:
                shading = True  # one of its materials changed (whose own update comes with it), or its shading
                continue
            if idb.type == "MESH" and idb.name in vp.mesh_names and not u.is_updated_geometry:
                if u.is_updated_transform:
                    transforms[idb.name] = matrix(idb.matrix_world)
                continue
            full = True
        elif isinstance(idb, bpy.types.Light):
            lights = True
        elif isinstance(idb, bpy.types.Material):
            materials = True
        elif isinstance(idb, bpy.types.Image):
            materials = True  # images are read through the materials' texture nodes
            full |= _world_uses_image(depsgraph.scene, idb)
        elif isinstance(idb, bpy.types.ShaderNodeTree):
            trees = True  # a material's, light's or world's tree: its owner's update comes with it
        elif isinstance(idb, bpy.types.Mesh) and not u.is_updated_geometry:
            shading = True  # a material of the mesh changed (its Material update comes with it)
        elif isinstance(idb, bpy.types.Camera | bpy.types.Screen | bpy.types.WorkSpace | bpy.types.Scene):
            continue  # a Scene update comes with every edit; what changed in it arrives as its own update
        else:
            full = True
    # a node tree or a mesh's shading changed without a material, light or world update saying why: re-export
    full |= (trees or shading) and not (materials or lights)
    if not (transforms or full or lights or materials):
        return None
    if not full and materials:
        mats = export.export_materials(depsgraph, vp.material_reads)[0]
        full = mats is None  # the meshes' export depends on what changed (UV maps, baking)
    if full:
        exp = export.export_scene(depsgraph, None)
        vp.mesh_names, vp.material_reads = unique_mesh_names(exp.scene), exp.material_reads
        return SceneEdit(transforms=transforms, scene=exp.scene)
    return SceneEdit(transforms=transforms, lights=export.export_lights(depsgraph)[0] if lights else None,
                     materials=mats)


def _world_uses_image(scene, image) -> bool:
    """Does the scene's world read `image` (an environment texture, also inside node groups): then an edit of the
    image is a world edit, which re-exports the scene."""
    world = scene.world
    name = (image.original or image).name
    trees, seen = [getattr(world, "node_tree", None)] if world is not None else [], set()
    while trees:
        tree = trees.pop()
        if tree is None or tree.name in seen:
            continue
        seen.add(tree.name)
        for n in tree.nodes:
            if getattr(getattr(n, "image", None), "name", None) == name:
                return True
            trees.append(getattr(n, "node_tree", None))
    return False


def view_draw(engine, context, depsgraph) -> None:
    """RenderEngine.view_draw: never raises."""
    try:
        _view_draw(engine, context, depsgraph)
    except Exception as exc:
        traceback.print_exc()
        engine.update_stats("", f"restircl: unexpected {type(exc).__name__}: {exc}")


def region_camera(context, pixel_size: int, depsgraph=None):
    """The restircl.Camera of the 3D view in `context` at the render size of its region; through the camera
    (Camera View) with that camera's depth of field (viewport_lens)."""
    region, rv3d = context.region, context.region_data
    w, h = scaled_size(region.width, region.height, pixel_size)
    ortho_view = not rv3d.is_perspective and rv3d.view_perspective != "CAMERA"
    back = 0.5 * float(context.space_data.clip_end) if ortho_view else 0.0
    thin_lens = view_lens(context, depsgraph) if depsgraph is not None else None
    return view_camera(matrix(rv3d.view_matrix), matrix(rv3d.window_matrix), w, h, back, thin_lens)


def _view_draw(engine, context, depsgraph) -> None:
    vp = getattr(engine, "viewport", None)
    if vp is None or vp.session is None:
        engine.update_stats("", f"restircl: {vp.message if vp is not None else 'no scene'}")
        return
    session = vp.session
    session.set_view(region_camera(context, depsgraph.scene.restircl.viewport_pixel_size, depsgraph))
    frame = session.latest()
    if frame is not None:
        draw_frame(engine, depsgraph.scene, vp, frame, context.region.width, context.region.height)
    engine.update_stats("", session.status_text())
    if session.error is None and (frame is None or frame.samples < session.sample_limit):
        engine.tag_redraw()  # poll for the next frame


def draw_frame(engine, scene, vp: Viewport, frame, width: int, height: int) -> None:
    """The frame, stretched over the region (bilinear), uploaded once per frame. bind_display_space_shader binds
    Blender's image shader (Blender 5.0; the scene is not used): the frame's scene-linear values go into the 3D
    view's colour buffer as they are, and Blender applies the view transform to that buffer afterwards, as for
    Cycles. Needs a GPU context: tests/blender/test_viewport_draw.py draws into an offscreen of background bpy."""
    import gpu
    from gpu_extras.presets import draw_texture_2d

    if vp.texture_index != frame.index:
        h, w = frame.rgba.shape[:2]
        data = gpu.types.Buffer("FLOAT", w * h * 4, frame.rgba.ravel())
        vp.texture, vp.texture_index = gpu.types.GPUTexture((w, h), format="RGBA16F", data=data), frame.index
    gpu.state.blend_set("ALPHA_PREMULT")
    engine.bind_display_space_shader(scene)
    draw_texture_2d(vp.texture, (0, 0), width, height)
    engine.unbind_display_space_shader()
    gpu.state.blend_set("NONE")
