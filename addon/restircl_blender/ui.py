"""Panels of the restircl engine (shown only when it is the active engine: the COMPAT_ENGINES pattern), and
our engine added to the built-in light, material and post-processing panels that apply to it."""

from __future__ import annotations

import bpy

from . import engine

ENGINE = "RESTIRCL"
# Built-in panels whose settings restircl reads (light type/colour/power/shape, material surface nodes).
BUILTIN_PANELS = (
    "DATA_PT_EEVEE_light", "DATA_PT_spot", "NODE_DATA_PT_EEVEE_light",
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface",
    "RENDER_PT_post_processing",
)
_added_to: list[str] = []


class RestirclPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class RESTIRCL_PT_sampling(RestirclPanel, bpy.types.Panel):
    bl_label = "Sampling"

    def draw(self, context):
        props = context.scene.restircl
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(props, "method")
        col = layout.column(align=True)
        col.prop(props, "samples", text="Still Samples")
        col.prop(props, "target_error")
        col.prop(props, "warmup_frames")
        sub = layout.column()
        sub.active = props.method in ("ris", "restir")
        sub.prop(props, "candidates")
        sub.prop(props, "light_tiles")
        layout.prop(props, "seed")


class RESTIRCL_PT_reuse(RestirclPanel, bpy.types.Panel):
    bl_label = "Reuse"
    bl_parent_id = "RESTIRCL_PT_sampling"

    def draw(self, context):
        props = context.scene.restircl
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.active = props.method == "restir"
        layout.prop(props, "temporal")
        sub = layout.column()
        sub.active = props.temporal
        sub.prop(props, "m_cap")
        layout.prop(props, "spatial")
        sub = layout.column(align=True)
        sub.active = props.spatial
        sub.prop(props, "spatial_neighbours")
        sub.prop(props, "spatial_radius")
        sub.prop(props, "spatial_passes")
        layout.prop(props, "bias_correction")
        layout.prop(props, "visibility_reuse")


class RESTIRCL_PT_taa(RestirclPanel, bpy.types.Panel):
    bl_label = "Temporal Anti-Aliasing"

    def draw_header(self, context):
        self.layout.prop(context.scene.restircl, "taa", text="")

    def draw(self, context):
        props = context.scene.restircl
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.active = props.taa
        layout.prop(props, "alpha_min")
        layout.prop(props, "gamma")


class RESTIRCL_PT_device(RestirclPanel, bpy.types.Panel):
    bl_label = "Device"
    bl_options = {"DEFAULT_CLOSED"}
    _devices: list[str] | None = None

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(context.scene.restircl, "device")
        if RESTIRCL_PT_device._devices is None:  # listing devices loads the OpenCL ICDs: do it once
            RESTIRCL_PT_device._devices = engine.device_list()
        col = layout.column(align=True)
        for label in RESTIRCL_PT_device._devices:
            col.label(text=label)


class RESTIRCL_PT_passes(RestirclPanel, bpy.types.Panel):
    bl_label = "Passes"
    bl_context = "view_layer"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        vl = context.view_layer
        col = layout.column(heading="Data", align=True)
        col.prop(vl, "use_pass_z")
        col.prop(vl, "use_pass_normal")
        col.prop(vl, "use_pass_vector")
        col = layout.column(heading="Light", align=True)
        col.prop(vl.restircl, "use_pass_noisy_direct")


CLASSES = (RESTIRCL_PT_sampling, RESTIRCL_PT_reuse, RESTIRCL_PT_taa, RESTIRCL_PT_device, RESTIRCL_PT_passes)


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
