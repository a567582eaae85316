"""Shadow rays through smooth thin walls (opencl/bvh/thin_wall_shadow.h): the record of a material that Cycles 5.3
makes transparent to every ray but the camera's, a Principled BSDF with Thin Wall whose transmission is smooth.
It follows the material's coverage record in the Tri array's tail (upload/alpha.py), so shadow rays read it from
the BVH's own buffers.

A wall qualifies when the rays can evaluate it from the triangle alone: one Principled closure (no Mix or Add
Shader), Thin Wall on, Transmission Weight > 0, and constant Base Color, Metallic, Roughness and Specular Tint;
smooth as the wall's lobe decides it (opencl/bsdf/closures/thin_wall.h: alpha^2 and the transmission's roughened
alpha_t^2 at most 2e-10, in float32). Other thin walls keep stopping shadow rays (docs/blender.md)."""

from __future__ import annotations

import numpy as np

from ..materials.material import Material
from ..materials.textures import constant_float, constant_rgb, is_texture
from ..materials.thin_film import has_film
from ..scene.scene import Scene

THIN_RECORD = 2  # float4s: (Base Color, IOR), (Specular Tint, transmission weight)
SMOOTH = np.float32(2e-10)


def _smooth(roughness: float, ior: float) -> bool:
    """The lobe's test, in float32 as the kernel computes it."""
    f = np.float32
    r = f(min(max(roughness, 0.0), 1.0))
    alpha = r * r
    eta = f(max(ior, 1e-5))
    k = f(3.4) * (eta - f(1)) * (eta - f(0.5)) ** 2 / (eta * eta * eta)
    alpha_t = f(min(max(float(alpha * np.sqrt(k)), 0.0), 1.0)) if k > 0 else f(0)
    return bool(alpha * alpha <= SMOOTH and alpha_t * alpha_t <= SMOOTH)


def thin_wall_record(m: Material) -> np.ndarray | None:
    """The (THIN_RECORD, 4) float32 record of m where shadow rays pass it, else None."""
    if m.layers or m.kind != "principled" or not m.thin_wall or not float(m.transmission) > 0:
        return None
    if has_film(m):  # the filmed Principled resolve has no sheet (bsdf/closures/principled_thin_film.h)
        return None
    if any(is_texture(v) for v in (m.albedo, m.metallic, m.roughness, m.specular_tint)):
        return None
    metallic = min(max(constant_float(m.metallic), 0.0), 1.0)
    weight = (1.0 - metallic) * min(float(m.transmission), 1.0)
    if not weight > 0 or not _smooth(constant_float(m.roughness), float(m.ior)):
        return None
    rec = np.zeros((THIN_RECORD, 4), np.float32)
    rec[0] = (*constant_rgb(m.albedo), max(float(m.ior), 1e-5))
    rec[1] = (*np.maximum(constant_rgb(m.specular_tint), 0.0), weight)
    return rec


def scene_has_thin_shadow(scene: Scene) -> bool:
    """Whether some material is a thin wall that shadow rays pass (the HAS_THIN_SHADOW flag)."""
    return any(thin_wall_record(m) is not None for m in scene.materials)
