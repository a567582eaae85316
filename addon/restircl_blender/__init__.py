"""restircl for Blender: a render engine for many-light direct lighting (ReSTIR DI + TAA) in OpenCL.

Installed as a Blender extension (blender_manifest.toml, wheels bundled by tools/build_extension.py), or used
as a plain package in any bpy process:

    import sys; sys.path.insert(0, "addon")
    import restircl_blender
    restircl_blender.register()
    bpy.context.scene.render.engine = "RESTIRCL"

The engine class is thin; the work is in engine.py (render jobs), render_result.py (a frame into the Render
Result), passes.py (the passes a view layer has on), preview.py (material previews), viewport.py (the Rendered
viewport), export/ (depsgraph -> restircl.Scene), properties.py (settings), light_paths.py (the Light Paths
read from Cycles' settings) and ui.py (panels).
"""

from __future__ import annotations

import bpy
from bpy.app.handlers import persistent

from . import engine, passes, properties, ui, viewport

bl_info = {  # for installing the folder as a legacy add-on; the extension uses blender_manifest.toml
    "name": "restircl",
    "description": "Many-light direct lighting (ReSTIR DI, TAA) in OpenCL",
    "blender": (4, 2, 0),
    "version": (0, 1, 0),
    "category": "Render",
}


class RestirclRenderEngine(bpy.types.RenderEngine):
    bl_idname = "RESTIRCL"
    bl_label = "restircl"
    bl_use_preview = True  # material previews: preview.py
    bl_use_postprocess = True
    bl_use_eevee_viewport = True  # the Material Preview shading mode uses EEVEE; Rendered uses view_draw
    bl_use_shading_nodes_custom = False  # materials use Blender's shader nodes

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.viewport = None  # viewport.Viewport of a Rendered 3D view

    def __del__(self):
        # Blender may have freed the engine's RNA already (after a failed render, at exit): nothing is left to free
        try:
            self.free()
        except ReferenceError:
            pass

    def free(self):
        viewport.free(self)

    def view_update(self, context, depsgraph):
        viewport.view_update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        viewport.view_draw(self, context, depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        passes.register_passes(self, scene, renderlayer)

    def render(self, depsgraph):
        engine.render(self, depsgraph)


@persistent
def _on_render_done(*_args):
    engine.clear_animation_sessions()


@persistent
def _on_load(*_args):
    engine.clear_sessions()


_HANDLERS = (
    (bpy.app.handlers.render_complete, _on_render_done),
    (bpy.app.handlers.render_cancel, _on_render_done),
    (bpy.app.handlers.load_pre, _on_load),
)


def register() -> None:
    properties.register()
    bpy.utils.register_class(RestirclRenderEngine)
    ui.register()
    for handlers, fn in _HANDLERS:
        if fn not in handlers:
            handlers.append(fn)


def unregister() -> None:
    for handlers, fn in _HANDLERS:
        if fn in handlers:
            handlers.remove(fn)
    engine.clear_sessions()
    ui.unregister()
    bpy.utils.unregister_class(RestirclRenderEngine)
    properties.unregister()
