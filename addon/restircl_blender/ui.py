"""Panels of the restircl engine (shown only when it is the active engine: the COMPAT_ENGINES pattern), and
our engine added to the built-in light, material and post-processing panels that apply to it, and to Cycles' Light
Paths panels (restircl reads them from the scene's Cycles settings: light_paths.py)."""

from __future__ import annotations

import bpy
from restircl.render.passes import PASSES

from . import engine, light_paths, passes, properties

ENGINE = "RESTIRCL"
# Built-in panels whose settings restircl reads (light type/colour/power/shape, material surface nodes).
BUILTIN_PANELS = (
    "DATA_PT_EEVEE_light", "DATA_PT_spot", "NODE_DATA_PT_EEVEE_light",
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface",
    "RENDER_PT_post_processing",
)
# Cycles' Light Paths and their sub-panels whose settings restircl reads (light_paths.FROM_CYCLES): with Cycles
# enabled the user sets the bounces once for both engines, and restircl's own Light Paths panel hides
CYCLES_PANELS = ("CYCLES_RENDER_PT_light_paths", "CYCLES_RENDER_PT_light_paths_max_bounces",
                 "CYCLES_RENDER_PT_light_paths_clamping")
_added_to: list[tuple[str, bool]] = []  # panel, whether we gave it its COMPAT_ENGINES


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


def refusal(props) -> tuple[str, tuple[str, ...]] | None:
    """Why the core refuses the settings the panels hold together, or None. Each property's range is one the core
    accepts alone; a joint limit (Tile Count x Tile Size, settings.table.JOINT_LIMITS) is checked only on the whole
    settings, so the panel says it next to the values instead of letting the render stop on it."""
    import restircl

    try:
        properties.make_settings(restircl, props).validate()
    except restircl.SettingError as exc:
        return str(exc), tuple(exc.names)
    return None


def draw_settings(layout, props, settings, panel: str, skip: str | None = None) -> None:
    col = layout.column()
    refused = refusal(props)
    names = refused[1] if refused is not None else ()
    for d in settings:
        if d.spec.panel != panel or d.name == skip:
            continue
        row = col.row()
        row.active = all(getattr(props, name) in values for name, values in d.spec.applies_when)
        row.alert = d.name in names
        row.prop(props, d.name)
    if refused is not None and any(d.spec.panel == panel and d.name in names for d in settings):
        col.label(text=refused[0], icon="ERROR")


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


class RESTIRCL_PT_gi(RestirclPanel, bpy.types.Panel):
    """ReSTIR GI: reuse of the bounced light in animation and viewport frames (with Light Paths > Max Bounces > 0)."""

    bl_label = "Global Illumination Reuse"
    bl_parent_id = "RESTIRCL_PT_sampling"
    bl_options = {"DEFAULT_CLOSED"}
    settings_panel = "gi"
    header = "gi_reuse"


class RESTIRCL_PT_taa(RestirclPanel, bpy.types.Panel):
    bl_label = "Temporal Anti-Aliasing"
    settings_panel = "taa"
    header = "taa"


class RESTIRCL_PT_light_paths(RestirclPanel, bpy.types.Panel):
    """restircl's own Light Paths, for a Blender without the Cycles add-on (else Cycles' panels show them)."""

    bl_label = "Light Paths"
    bl_options = {"DEFAULT_CLOSED"}
    settings_panel = "light_paths"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and light_paths.cycles_of(context.scene) is None


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


CLASSES = (RESTIRCL_PT_sampling, RESTIRCL_PT_viewport, RESTIRCL_PT_lights, RESTIRCL_PT_reuse, RESTIRCL_PT_gi,
           RESTIRCL_PT_light_paths, RESTIRCL_PT_taa, RESTIRCL_PT_device, RESTIRCL_PT_passes)


def register() -> None:
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    for name in BUILTIN_PANELS + CYCLES_PANELS:  # Cycles' where the Cycles add-on is enabled
        _add_engine(name)


def _add_engine(name: str) -> None:
    """Add RESTIRCL to the COMPAT_ENGINES of panel `name`. A panel that inherits the set (all of Cycles' share the
    one of their base class) gets a set of its own: adding to the shared one would show every Cycles panel."""
    panel = getattr(bpy.types, name, None)
    compat = getattr(panel, "COMPAT_ENGINES", None)
    if compat is None or ENGINE in compat:
        return
    own = "COMPAT_ENGINES" in vars(panel)
    if own:
        compat.add(ENGINE)
    else:
        panel.COMPAT_ENGINES = {*compat, ENGINE}
    _added_to.append((name, not own))


def unregister() -> None:
    for name, made in _added_to:
        panel = getattr(bpy.types, name, None)
        if panel is None:
            continue
        if made and "COMPAT_ENGINES" in vars(panel):
            del panel.COMPAT_ENGINES  # the inherited set again
        elif "COMPAT_ENGINES" in vars(panel):
            panel.COMPAT_ENGINES.discard(ENGINE)
    _added_to.clear()
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
