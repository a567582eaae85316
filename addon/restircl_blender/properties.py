"""Render settings of the restircl engine: `scene.restircl` and `view_layer.restircl`."""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

METHODS = [
    ("restir", "ReSTIR", "Reservoir resampling with temporal and spatial reuse"),
    ("ris", "RIS", "Resampled importance sampling over light-array candidates, no reuse"),
    ("light_array", "Light Array", "One light picked from the power-proportional light array"),
    ("uniform", "Uniform", "One light picked uniformly"),
    ("reference", "Reference", "Many-sample estimator for ground truth (slow)"),
]
BIAS_MODES = [
    ("pairwise", "Pairwise MIS (unbiased)", "Weigh each neighbour's sample against this pixel's by their targets "
     "(balance heuristic in pairs): unbiased and robust next to small or touching lights"),
    ("z_count", "1/Z (unbiased)", "Divide by the number of reservoirs whose sample could have produced this "
     "pixel's sample"),
    ("none", "None (biased)", "Plain M-weighted merge: faster, darkens at contact shadows"),
]
LIGHT_TILES = [
    ("auto", "Auto", "Presampled light tiles from 20,000 lights on, where the lights no longer fit the CPU cache"),
    ("on", "On", "Draw the RIS candidates from presampled light tiles"),
    ("off", "Off", "Draw the RIS candidates from the whole light array"),
]

# Blender's render settings -> restircl.Settings keyword arguments (property name == keyword).
SETTINGS_KEYS = ("method", "candidates", "temporal", "spatial", "spatial_neighbours", "spatial_radius",
                 "spatial_passes", "bias_correction", "m_cap", "visibility_reuse", "taa", "alpha_min", "gamma",
                 "seed", "light_tiles")


class RestirclRenderSettings(bpy.types.PropertyGroup):
    method: EnumProperty(name="Method", items=METHODS, default="restir",
                         description="Direct-light estimator")
    samples: IntProperty(name="Samples", default=16, min=1, soft_max=1024, max=1 << 20,
                         description="Frames accumulated with a still camera for a still render (F12)")
    target_error: FloatProperty(name="Target Error", default=0.0, min=0.0, soft_max=0.1, precision=4,
                                description="Still render: stop before Samples once the estimated relMSE of the "
                                "image (from two half buffers, no reference) reaches this; 0 = off")
    warmup_frames: IntProperty(name="Warm-up Frames", default=0, min=0, max=256,
                               description="Frames before the first frame of an animation render that are "
                               "rendered (with their motion) and discarded, to fill the ReSTIR and TAA history")
    candidates: IntProperty(name="Candidates", default=8, min=1, max=256,
                            description="Light candidates per pixel and frame (RIS, ReSTIR)")
    temporal: BoolProperty(name="Temporal Reuse", default=True,
                           description="Merge the reprojected reservoir of the previous frame")
    spatial: BoolProperty(name="Spatial Reuse", default=True, description="Merge neighbouring reservoirs")
    spatial_neighbours: IntProperty(name="Neighbours", default=3, min=1, max=32,
                                    description="Neighbour reservoirs merged per spatial pass")
    spatial_radius: FloatProperty(name="Radius", default=30.0, min=1.0, soft_max=100.0, max=1000.0,
                                  subtype="PIXEL", description="Radius of the spatial neighbourhood in pixels")
    spatial_passes: IntProperty(name="Passes", default=1, min=1, max=4, description="Spatial reuse passes")
    bias_correction: EnumProperty(name="Bias Correction", items=BIAS_MODES, default="pairwise")
    m_cap: FloatProperty(name="History Cap", default=20.0, min=1.0, soft_max=100.0, max=10000.0,
                         description="Cap of the temporal history M, as a multiple of the candidates")
    visibility_reuse: BoolProperty(name="Visibility Reuse", default=True,
                                   description="Trace a shadow ray for the initial sample before reuse")
    taa: BoolProperty(name="Temporal Anti-Aliasing", default=True,
                      description="Blend each frame with the reprojected, clipped colour history")
    alpha_min: FloatProperty(name="Minimum Blend", default=0.1, min=0.001, max=1.0,
                             description="Smallest weight of the new frame in the TAA blend")
    gamma: FloatProperty(name="Clip Gamma", default=1.0, min=0.0, soft_max=4.0, max=100.0,
                         description="Width of the TAA colour clipping box in standard deviations")
    seed: IntProperty(name="Seed", default=0, min=0, description="Random seed")
    light_tiles: EnumProperty(name="Light Tiles", items=LIGHT_TILES, default="auto",
                              description="RIS and ReSTIR: candidates from per-frame presampled light tiles (many "
                                          "lights)")
    device: StringProperty(name="Device", default="",
                           description="OpenCL device: 'P:D' (platform:device index) or part of its name; "
                           "empty = $RESTIRCL_DEVICE or the default choice")

    def settings_kwargs(self) -> dict:
        return {k: getattr(self, k) for k in SETTINGS_KEYS}


class RestirclViewLayerSettings(bpy.types.PropertyGroup):
    use_pass_noisy_direct: BoolProperty(name="Noisy Direct", default=True,
                                        description="The 1-sample direct light of the last frame, before TAA "
                                        "and accumulation")


CLASSES = (RestirclRenderSettings, RestirclViewLayerSettings)


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
