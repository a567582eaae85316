"""Panels of the restircl engine (shown only when it is the active engine: the COMPAT_ENGINES pattern), and
our engine added to the built-in light, material and post-processing panels that apply to it."""

from __future__ import annotations

import bpy
from restircl.render.passes import PASSES

from . import engine, passes, properties

ENGINE = "RESTIRCL"
# Built-in panels whose settings restircl reads (light type/colour/power/shape, material surface nodes).
BUILTIN_PANELS = (
    "DATA_PT_EEVEE_light", "DATA_PT_spot", "NODE_DATA_PT_EEVEE_light",
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface",
    "RENDER_PT_post_processing",
)
_added_to: list[str] = []


class RestirclPanel:
    """A panel that draws the settings the table puts in `settings_panel`, each greyed out where it has no effect."""

    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}
    settings_panel = ""
    header: str | None = None  # a bool setting drawn in the panel's header: the switch of what the panel holds

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw_header(self, context):
        if self.header is not None:
            self.layout.prop(context.scene.restircl, self.header, text="")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        draw_settings(layout, context.scene.restircl, properties.SCENE_SETTINGS, self.settings_panel, self.header)


def draw_settings(layout, props, settings, panel: str, skip: str | None = None) -> None:
    col = layout.column()
    for d in settings:
        if d.spec.panel != panel or d.name == skip:
            continue
        row = col.row()
        row.active = all(getattr(props, name) in values for name, values in d.spec.applies_when)
        row.prop(props, d.name)


class RESTIRCL_PT_sampling(RestirclPanel, bpy.types.Panel):
    bl_label = "Sampling"
    settings_panel = "sampling"


class RESTIRCL_PT_lights(RestirclPanel, bpy.types.Panel):
    bl_label = "Light Sampling"
    bl_parent_id = "RESTIRCL_PT_sampling"
    bl_options = {"DEFAULT_CLOSED"}
    settings_panel = "lights"


class RESTIRCL_PT_reuse(RestirclPanel, bpy.types.Panel):
    bl_label = "Reuse"
    bl_parent_id = "RESTIRCL_PT_sampling"
    settings_panel = "reuse"


class RESTIRCL_PT_taa(RestirclPanel, bpy.types.Panel):
    bl_label = "Temporal Anti-Aliasing"
    settings_panel = "taa"
    header = "taa"


class RESTIRCL_PT_viewport(RestirclPanel, bpy.types.Panel):
    bl_label = "Viewport"
    bl_parent_id = "RESTIRCL_PT_sampling"
    settings_panel = "viewport"


class RESTIRCL_PT_device(RestirclPanel, bpy.types.Panel):
    bl_label = "Device"
    bl_options = {"DEFAULT_CLOSED"}
    settings_panel = "device"
    _devices: list[str] | None = None

    def draw(self, context):
        RestirclPanel.draw(self, context)
        if RESTIRCL_PT_device._devices is None:  # listing devices loads the OpenCL ICDs: do it once
            RESTIRCL_PT_device._devices = engine.device_list()
        col = self.layout.column(align=True)
        for label in RESTIRCL_PT_device._devices:
            col.label(text=label)


class RESTIRCL_PT_passes(RestirclPanel, bpy.types.Panel):
    """The passes of restircl.render.passes.PASSES that can be turned off, under Blender's own headings."""

    bl_label = "Passes"
    bl_context = "view_layer"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        vl = context.view_layer
        for heading, light in (("Data", False), ("Light", True)):
            col = layout.column(heading=heading, align=True)
            for p in PASSES:
                if p.blender_toggle is not None and (p.blender_type == "COLOR") == light:
                    owner, name = passes.toggle_owner(vl, p.blender_toggle)
                    col.prop(owner, name)


CLASSES = (RESTIRCL_PT_sampling, RESTIRCL_PT_viewport, RESTIRCL_PT_lights, RESTIRCL_PT_reuse, RESTIRCL_PT_taa,
           RESTIRCL_PT_device, RESTIRCL_PT_passes)


def register() -> None:
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    for name in BUILTIN_PANELS:
        panel = getattr(bpy.types, name, None)
        compat = getattr(panel, "COMPAT_ENGINES", None)
        if compat is not None and ENGINE not in compat:
            compat.add(ENGINE)
            _added_to.append(name)


def unregister() -> None:
    for name in _added_to:
        panel = getattr(bpy.types, name, None)
        compat = getattr(panel, "COMPAT_ENGINES", None)
        if compat is not None:
            compat.discard(ENGINE)
    _added_to.clear()
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
