"""The passes (AOVs) of a Frame, declared once: where each goes in an EXR file and in Blender's Render Result."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Pass:
    attr: str  # the Frame field holding it, (H, W) or (H, W, C)
    channels: str  # one letter per channel: the EXR channel suffixes and Blender's chan_id
    exr_layer: str  # EXR layer name ("" for the unprefixed R, G, B, A of the image)
    blender: str  # Blender's pass name
    blender_type: str  # Blender's pass type: COLOR, VALUE or VECTOR
    # the view layer property that turns the pass on in Blender (dotted: one of the add-on's); None: always on
    blender_toggle: str | None
    miss: float | None = None  # written instead of inf where the camera ray hits nothing (as Blender does)
    blender_4: str | None = None  # its name before Blender 5.0 (which renamed the built-in passes), if other
    requires: str | None = None  # a render setting (scene.restircl) without which the pass does not exist


DEPTH_MISS = 1e10
PASSES = (
    Pass("color", "RGBA", "", "Combined", "COLOR", None),
    Pass("depth", "Z", "Depth", "Depth", "VALUE", "use_pass_z", miss=DEPTH_MISS),
    Pass("normal", "XYZ", "Normal", "Normal", "VECTOR", "use_pass_normal"),
    Pass("vector", "XYZW", "Vector", "Vector", "VECTOR", "use_pass_vector"),
    Pass("noisy", "RGB", "Noisy", "Noisy Direct", "COLOR", "restircl.use_pass_noisy_direct"),
    # the surface's diffuse albedo is what Cycles writes as Diffuse Color, the pass compositors and denoisers
    # (OIDN's Albedo input) take from it
    Pass("albedo", "RGB", "Albedo", "Diffuse Color", "COLOR", "use_pass_diffuse_color", blender_4="DiffCol"),
    # the image before the denoiser, as Cycles keeps it when denoising
    Pass("noisy_image", "RGBA", "NoisyImage", "Noisy Image", "COLOR", None, requires="denoise"),
    # Cycles' light passes (Settings.light_passes; docs/design.md "Light passes"): the direct and the bounced light
    # of the diffuse, the glossy and the transmission parts of the first surface, each divided by its colour pass,
    # and what the camera sees of the emitters and of the world
    Pass("diffuse_direct", "RGB", "DiffDir", "Diffuse Direct", "COLOR", "use_pass_diffuse_direct",
         blender_4="DiffDir", requires="light_passes"),
    Pass("diffuse_indirect", "RGB", "DiffInd", "Diffuse Indirect", "COLOR", "use_pass_diffuse_indirect",
         blender_4="DiffInd", requires="light_passes"),
    Pass("glossy_direct", "RGB", "GlossDir", "Glossy Direct", "COLOR", "use_pass_glossy_direct",
         blender_4="GlossDir", requires="light_passes"),
    Pass("glossy_indirect", "RGB", "GlossInd", "Glossy Indirect", "COLOR", "use_pass_glossy_indirect",
         blender_4="GlossInd", requires="light_passes"),
    Pass("glossy_color", "RGB", "GlossCol", "Glossy Color", "COLOR", "use_pass_glossy_color", blender_4="GlossCol",
         requires="light_passes"),
    Pass("transmission_direct", "RGB", "TransDir", "Transmission Direct", "COLOR", "use_pass_transmission_direct",
         blender_4="TransDir", requires="light_passes"),
    Pass("transmission_indirect", "RGB", "TransInd", "Transmission Indirect", "COLOR",
         "use_pass_transmission_indirect", blender_4="TransInd", requires="light_passes"),
    Pass("transmission_color", "RGB", "TransCol", "Transmission Color", "COLOR", "use_pass_transmission_color",
         blender_4="TransCol", requires="light_passes"),
    Pass("emission", "RGB", "Emit", "Emission", "COLOR", "use_pass_emit", blender_4="Emit", requires="light_passes"),
    Pass("environment", "RGB", "Env", "Environment", "COLOR", "use_pass_environment", blender_4="Env",
         requires="light_passes"),
    # Cycles' Object Index and Material Index: the pass index of what the camera ray hit (render/index_passes.py)
    Pass("object_index", "X", "IndexOB", "Object Index", "VALUE", "use_pass_object_index", blender_4="IndexOB"),
    Pass("material_index", "X", "IndexMA", "Material Index", "VALUE", "use_pass_material_index", blender_4="IndexMA"),
)
# The per-pixel planes the kernels write where light passes are on (LPASS_* in opencl/codes.h, in this order): the
# light of each kind before any division, and the colours of the first surface (render/light_passes.py divides)
LIGHT_PLANES = ("diffuse_direct", "diffuse_indirect", "glossy_direct", "glossy_indirect", "emission", "environment",
                "diffuse_color", "glossy_color", "transmission_direct", "transmission_indirect", "transmission_color")


def blender_name(p: Pass, version: tuple[int, ...]) -> str:
    """The pass's name in Blender `version` (bpy.app.version)."""
    return p.blender_4 if p.blender_4 is not None and tuple(version) < (5, 0, 0) else p.blender


def exr_names(p: Pass) -> list[str]:
    """The EXR channel names of a pass, in channel order: Depth.Z, Normal.X, ..., or R, G, B, A."""
    return [f"{p.exr_layer}.{c}" if p.exr_layer else c for c in p.channels]
