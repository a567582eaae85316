"""Materials -> the device's Material records and closure table (opencl/types.h: Material, Closure).

Each Material becomes one record and 1..MAX_LAYERS closures. A constant input is stored as it is; a texture node
input gets the index of its node in the texture program (TexturePacker, python/restircl/upload/textures.py), or
TEX_NONE when no packer is given (the constant fields then hold a neutral value and the caller has warned).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..core import layouts as L
from ..materials.material import Material, material_inputs
from ..materials.textures import Input, is_texture

#: an input without a texture node (TEX_NONE in opencl/codes.h)
TEX_NONE = -1
#: closure kinds by their device code (CLOSURE_* in opencl/codes.h)
KIND_CODE = {"principled": 0, "diffuse": 1, "glossy": 2}
#: Material.info.w: the two closures are mixed by closure 1's weight w (1 - w, w); else added
MATERIAL_MIX = 1

# a texture node -> its index in the texture program (python/restircl/upload/textures.py)
TextureIndex = Callable[[object], int]


def _no_textures(_node: object) -> int:
    return TEX_NONE


def constant_rgb(value: Input, neutral: tuple = (1.0, 1.0, 1.0)) -> tuple[float, float, float]:
    if is_texture(value):
        return neutral
    a = np.broadcast_to(np.asarray(value, dtype=np.float64), (3,))
    return float(a[0]), float(a[1]), float(a[2])


def constant_float(value: Input, neutral: float = 0.0) -> float:
    if is_texture(value):
        return neutral
    a = np.asarray(value, dtype=np.float64).reshape(-1)
    return float(a[0]) if a.size == 1 else float(a.mean())


def closures_of(m: Material) -> list[Material]:
    return list(m.layers) if m.layers else [m]


def uses_glossy(m: Material) -> bool:
    """Whether any closure of m has a specular lobe (Principled with Specular IOR Level > 0 or Metallic > 0, or a
    Glossy BSDF); textured metallic/specular counts as having one."""
    for c in closures_of(m):
        if c.kind == "glossy":
            return True
        if c.kind == "principled":
            if is_texture(c.metallic) or is_texture(c.specular):
                return True
            if constant_float(c.metallic) > 0 or constant_float(c.specular) > 0:
                return True
    return False


def uses_textures(m: Material) -> bool:
    return any(is_texture(v) for v in material_inputs(m))


def diffuse_albedo(m: Material) -> tuple[float, float, float]:
    """The albedo diffuse-only builds shade with (Material.albedo): the closures' constant colours summed with
    their weights ((1 - f, f) for a Mix, (1, 1) for an Add; a textured factor counts as 0.5). Glossy builds resolve
    the closures per pixel instead (opencl/bsdf/principled.h)."""
    cl = closures_of(m)
    if len(cl) == 1:
        return constant_rgb(cl[0].albedo, (0.8, 0.8, 0.8))
    f = constant_float(m.mix, 0.5) if m.mix is not None else None
    weights = (1.0 - f, f) if f is not None else (1.0, 1.0)
    total = sum(w * np.asarray(constant_rgb(c.albedo, (0.8, 0.8, 0.8))) for c, w in zip(cl, weights, strict=True))
    return float(total[0]), float(total[1]), float(total[2])


@dataclass
class PackedMaterials:
    materials: np.ndarray  # L.MATERIAL
    closures: np.ndarray  # L.CLOSURE
    glossy: bool  # some material has a specular lobe: HAS_GLOSSY
    textured: bool  # some input is a texture: HAS_TEXTURES


def pack_materials(materials: Sequence[Material], texture_index: TextureIndex = _no_textures) -> PackedMaterials:
    recs = np.zeros(max(len(materials), 1), L.MATERIAL)
    recs["info"][:] = (0, 0, TEX_NONE, 0)
    rows: list[np.void] = []
    for i, m in enumerate(materials):
        cl = closures_of(m)
        recs["albedo"][i, :3] = diffuse_albedo(m)
        recs["emission"][i, :3] = m.radiance
        recs["emission"][i, 3] = float(m.is_emissive)
        flags = MATERIAL_MIX if (m.layers and m.mix is not None) else 0
        recs["info"][i] = (len(rows), len(cl), texture_index(m.emission) if is_texture(m.emission) else TEX_NONE,
                           flags)
        for k, c in enumerate(cl):
            weight: Input = 1.0 if (not m.layers or m.mix is None) else m.mix
            rows.append(_closure(c, weight, first=k == 0 and flags == MATERIAL_MIX, tex=texture_index))
    closures = np.zeros(max(len(rows), 1), L.CLOSURE)
    for k, r in enumerate(rows):
        closures[k] = r
    return PackedMaterials(recs, closures, any(map(uses_glossy, materials)), any(map(uses_textures, materials)))


def _closure(c: Material, weight: Input, first: bool, tex: TextureIndex) -> np.void:
    """One closure record. For a Mix the weight stored is the factor f for both closures; the kernel uses 1 - f for
    the first (`first`, kind.z = 1) and f for the second."""
    def t(v: Input) -> int:
        return tex(v) if is_texture(v) else TEX_NONE

    r = np.zeros((), L.CLOSURE)
    r["base"][:3] = constant_rgb(c.albedo, (0.8, 0.8, 0.8))
    r["base"][3] = constant_float(c.metallic)
    r["spec"] = (constant_float(c.roughness, 0.5), float(c.ior), constant_float(c.specular),
                 constant_float(weight, 0.5))
    r["tint"][:3] = constant_rgb(c.specular_tint)
    r["kind"] = (KIND_CODE[c.kind], int(c.distribution == "multi_ggx"), int(first), 0)
    r["tex"] = (t(c.albedo), t(c.metallic), t(c.roughness), t(c.specular))
    r["tex2"] = (t(c.specular_tint), t(c.normal) if c.normal is not None else TEX_NONE, t(weight), TEX_NONE)
    return r
