"""Render settings of the restircl engine, `scene.restircl` and `view_layer.restircl`, generated from restircl's
settings table (restircl/settings/table.py) and the add-on's own settings below, which are declared the same way: one
Blender property per setting, with the table's label, description, default, choices and range."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from restircl import Settings
from restircl.settings.spec import Declared, Range, declared, setting

from . import cryptomatte, light_paths, passes

INT_MIN, INT_MAX = -(1 << 31), (1 << 31) - 1  # Blender's IntProperty holds a C int


@dataclass
class EngineSettings:
    """The add-on's settings that are not restircl.Settings: how a render job drives the renderer."""

    samples: int = setting(16, "Still Samples", "Frames accumulated with a still camera for a still render (F12)",
                           range=Range(int, 1, 1 << 20), panel="sampling", soft_max=1024)
    target_error: float = setting(0.0, "Target Error", "Still render: stop before Samples once the estimated relMSE "
                                  "of the image (from two half buffers, no reference) reaches this; 0 = off",
                                  range=Range(float, 0, finite=True), panel="sampling", soft_max=0.1, precision=4)
    preview_samples: int = setting(16, "Preview Samples", "Material previews (the Material tab's preview and the "
                                   "material icons): frames accumulated for each", range=Range(int, 1, 1 << 16),
                                   panel="viewport", soft_max=256)
    viewport_samples: int = setting(128, "Viewport Samples", "Rendered viewport: frames averaged while the view "
                                    "stays still, after which the viewport stops rendering until something changes",
                                    range=Range(int, 1, 1 << 20), panel="viewport", soft_max=4096)
    viewport_pixel_size: int = setting(2, "Pixel Size", "Rendered viewport: render one pixel per this many screen "
                                       "pixels in each direction (as Cycles' Pixel Size; 2 renders a quarter of "
                                       "them)", range=Range(int, 1, 16), panel="viewport", soft_max=8)
    device: str = setting("", "Device", "OpenCL device: 'P:D' (platform:device index) or part of its name; empty = "
                          "$RESTIRCL_DEVICE or the default choice", panel="device")


@dataclass
class ViewLayerSettings:
    use_pass_noisy_direct: bool = setting(True, "Noisy Direct", "The 1-sample direct light of the last frame, "
                                          "before TAA and accumulation", panel="passes")


SCENE_SETTINGS = (*declared(Settings), *declared(EngineSettings))
RENDERER_SETTINGS = tuple(d.name for d in declared(Settings))  # what make_settings passes to restircl.Settings


def limits(d: Declared) -> tuple[float | None, float | None]:
    """Blender's hard min and max of a number setting: the smallest and largest allowed values (its `off` value
    included), ints within a C int."""
    r = d.spec.range
    if r is None:
        return None, None
    lo, hi = r.lowest(), r.highest()
    if r.off is not None:  # no maximum stays no maximum
        lo = r.off if lo is None else min(lo, r.off)
        hi = None if hi is None else max(hi, r.off)
    if d.kind is int:
        lo = INT_MIN if lo is None else max(int(lo), INT_MIN)
        hi = INT_MAX if hi is None else min(int(hi), INT_MAX)
    return lo, hi


def _snapper(name: str, r: Range) -> Any:
    """An update callback that moves a value Blender's min/max let through but the range refuses (between an `off`
    value and the range, e.g. a ratio of 0.5 where 0 is off and ratios start above 1) to the nearest allowed one."""

    def update(self: Any, _context: Any) -> None:
        value = getattr(self, name)
        snapped = r.nearest(value)
        if snapped != value:
            setattr(self, name, snapped)

    return update


def bpy_property(d: Declared) -> Any:
    spec = d.spec
    kw: dict[str, Any] = {"name": spec.label, "description": spec.description, "default": d.default}
    if spec.choices:
        items = [(c.id, c.label, c.description, c.number) for c in sorted(spec.choices, key=lambda c: c.number)]
        return EnumProperty(items=items, **kw)
    if d.kind is bool:
        return BoolProperty(**kw)
    if d.kind is str:
        return StringProperty(**kw)
    lo, hi = limits(d)
    kw.update({k: v for k, v in (("min", lo), ("max", hi), ("soft_max", spec.soft_max)) if v is not None})
    if spec.range is not None and spec.range.off is not None:
        kw["update"] = _snapper(d.name, spec.range)
    if d.kind is int:
        return IntProperty(**kw)
    return FloatProperty(subtype=spec.subtype, precision=spec.precision, **kw)


def _group(name: str, settings: tuple[Declared, ...], namespace: dict[str, Any]) -> type:
    annotations = {d.name: bpy_property(d) for d in settings}
    return type(name, (bpy.types.PropertyGroup,), {"__annotations__": annotations, **namespace})


def _settings_kwargs(self, scene=None) -> dict:
    """The keyword arguments of restircl.Settings: these properties, with the Light Paths that Cycles' settings of
    `scene` hold where it has them (light_paths.py); by default the scene that owns these properties."""
    kwargs = {name: getattr(self, name) for name in RENDERER_SETTINGS}
    kwargs.update(light_paths.read(self.id_data if scene is None else scene)[0])
    return kwargs


RestirclRenderSettings = _group("RestirclRenderSettings", SCENE_SETTINGS, {"settings_kwargs": _settings_kwargs})
RestirclViewLayerSettings = _group("RestirclViewLayerSettings", declared(ViewLayerSettings), {})
CLASSES = (RestirclRenderSettings, RestirclViewLayerSettings)


def make_settings(restircl, props, scene=None, view_layer=None):
    """restircl.Settings from scene.restircl (its properties are generated from the same table) and the Light Paths
    of `scene`'s Cycles settings (render_kwargs); `restircl` is the package the caller imported, so that the
    engine, the viewport and the previews report a missing one alike."""
    return restircl.Settings(**render_kwargs(props, scene, view_layer))


def render_kwargs(props, scene=None, view_layer=None) -> dict:
    """settings_kwargs, with the light passes on where `view_layer` (a render's) has one of their toggles on: the
    view layer's pass toggles decide them, as in Cycles (passes.light_passes_on)."""
    kwargs = props.settings_kwargs(scene)
    if view_layer is not None:
        kwargs["light_passes"] = passes.light_passes_on(view_layer)
        kwargs["cryptomatte_levels"] = cryptomatte.levels(view_layer)
    return kwargs


def register() -> None:
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.restircl = PointerProperty(type=RestirclRenderSettings, name="restircl")
    bpy.types.ViewLayer.restircl = PointerProperty(type=RestirclViewLayerSettings, name="restircl")


def unregister() -> None:
    del bpy.types.ViewLayer.restircl
    del bpy.types.Scene.restircl
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
