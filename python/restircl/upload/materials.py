"""Materials -> the device's Material records and closure table (opencl/types.h: Material, Closure).

Each Material becomes one record and 1..MAX_LAYERS closures. A closure packs the fields its kind reads
(materials/closures/: ClosureKind.fields) into their lanes of the Closure record (FIELD_LANES); the lanes of the
fields it ignores stay 0 and TEX_NONE. A constant input is stored as it is; a texture node input gets the index of
its node in the texture program (TexturePacker, python/restircl/upload/textures.py), or TEX_NONE when no packer is
given (the constant fields then hold a neutral value and the caller has warned).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..core import layouts as L
from ..materials.closures.registry import CLOSURE_KINDS, kind_of
from ..materials.material import Material, material_inputs
from ..materials.textures import Input, constant_float, constant_rgb, is_texture
from ..materials.thin_film import has_film

#: an input without a texture node (TEX_NONE in opencl/codes.h)
TEX_NONE = -1
#: closure kinds by their device code (CLOSURE_* in opencl/codes.h): each kind's code is its entry's
#: (materials/closures/registry.py)
KIND_CODE = {k.name: k.code for k in CLOSURE_KINDS}
#: Material.info.w: the two closures are mixed by closure 1's weight w (1 - w, w); else added
MATERIAL_MIX = 1
DEFAULT_ALBEDO = (0.8, 0.8, 0.8)  # what a textured colour stands for where no texture program is given

# a texture node -> its index in the texture program (python/restircl/upload/textures.py)
TextureIndex = Callable[[object], int]


def _no_textures(_node: object) -> int:
    return TEX_NONE


def closures_of(m: Material) -> list[Material]:
    return list(m.layers) if m.layers else [m]


def uses_glossy(m: Material) -> bool:
    """Whether any closure of m gives a lobe beyond the Lambert part (its kind's has_lobe: a Principled BSDF with
    Specular IOR Level or Metallic > 0, or a Glossy BSDF); a textured metallic/specular counts as having one."""
    return any(kind_of(c.kind).has_lobe(c) for c in closures_of(m))


def uses_transmission(m: Material) -> bool:
    """Whether any closure of m refracts (its kind's transmits: Glass, Refraction, a Principled BSDF's
    Transmission Weight > 0)."""
    return any(kind_of(c.kind).transmits(c) for c in closures_of(m))


def uses_thin_film(m: Material) -> bool:
    """Whether any closure of m has a thin film (of a kind that reads it, thicker than the cutoff)."""
    return any("thin_film_thickness" in kind_of(c.kind).fields and has_film(c) for c in closures_of(m))


def uses_textures(m: Material) -> bool:
    return any(is_texture(v) for v in material_inputs(m))


def diffuse_albedo(m: Material) -> tuple[float, float, float]:
    """The albedo diffuse-only builds shade with (Material.albedo): the closures' constant colours summed with
    their weights ((1 - f, f) for a Mix, (1, 1) for an Add; a textured factor counts as 0.5). Glossy builds resolve
    the closures per pixel instead (opencl/bsdf/resolve.h)."""
    cl = closures_of(m)
    if len(cl) == 1:
        return constant_rgb(cl[0].albedo, DEFAULT_ALBEDO)
    f = constant_float(m.mix, 0.5) if m.mix is not None else None
    weights = (1.0 - f, f) if f is not None else (1.0, 1.0)
    total = sum(w * np.asarray(constant_rgb(c.albedo, DEFAULT_ALBEDO)) for c, w in zip(cl, weights, strict=True))
    return float(total[0]), float(total[1]), float(total[2])


@dataclass
class PackedMaterials:
    materials: np.ndarray  # L.MATERIAL
    closures: np.ndarray  # L.CLOSURE
    glossy: bool  # some material has a specular lobe: HAS_GLOSSY
    textured: bool  # some input is a texture: HAS_TEXTURES
    transmission: bool = False  # some closure refracts: HAS_TRANSMISSION
    thin_film: bool = False  # some closure has a thin film: HAS_THIN_FILM


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
    return PackedMaterials(recs, closures, any(map(uses_glossy, materials)), any(map(uses_textures, materials)),
                           any(map(uses_transmission, materials)), any(map(uses_thin_film, materials)))


# A Material field -> its lanes of the Closure record (opencl/types.h, read by textures/closure_inputs.h):
# lanes(record, value, node) writes the constant and, for an input that may be a texture, node(value), its node
# in the texture program or TEX_NONE.
Lanes = Callable[[np.void, object, Callable[[object], int]], None]


def _albedo(r: np.void, v: object, node: Callable[[object], int]) -> None:
    r["base"][:3] = constant_rgb(v, DEFAULT_ALBEDO)
    r["tex"][0] = node(v)


def _metallic(r: np.void, v: object, node: Callable[[object], int]) -> None:
    r["base"][3] = constant_float(v)
    r["tex"][1] = node(v)


def _roughness(r: np.void, v: object, node: Callable[[object], int]) -> None:
    r["spec"][0] = constant_float(v, 0.5)
    r["tex"][2] = node(v)


def _ior(r: np.void, v: object, _node: Callable[[object], int]) -> None:
    r["spec"][1] = float(v)


def _specular(r: np.void, v: object, node: Callable[[object], int]) -> None:
    r["spec"][2] = constant_float(v)
    r["tex"][3] = node(v)


def _specular_tint(r: np.void, v: object, node: Callable[[object], int]) -> None:
    r["tint"][:3] = constant_rgb(v)
    r["tex2"][0] = node(v)


def _distribution(r: np.void, v: object, _node: Callable[[object], int]) -> None:
    r["kind"][1] = int(v == "multi_ggx")


def _normal(r: np.void, v: object, node: Callable[[object], int]) -> None:
    r["tex2"][1] = node(v)


def _transmission(r: np.void, v: object, _node: Callable[[object], int]) -> None:
    r["glass"][0] = float(v)  # type: ignore[arg-type]


def _thin_wall(r: np.void, v: object, _node: Callable[[object], int]) -> None:
    r["glass"][3] = 1.0 if v else 0.0  # type: ignore[index]
def _thin_film_thickness(r: np.void, v: object, _node: Callable[[object], int]) -> None:
    r["glass"][1] = float(v)  # type: ignore[arg-type]


def _thin_film_ior(r: np.void, v: object, _node: Callable[[object], int]) -> None:
    r["glass"][2] = float(v)  # type: ignore[arg-type]


FIELD_LANES: dict[str, Lanes] = {
    "albedo": _albedo, "metallic": _metallic, "roughness": _roughness, "ior": _ior, "specular": _specular,
    "specular_tint": _specular_tint, "distribution": _distribution, "normal": _normal, "transmission": _transmission,
    "thin_wall": _thin_wall,
    "thin_film_thickness": _thin_film_thickness, "thin_film_ior": _thin_film_ior,
}


def _closure(c: Material, weight: Input, first: bool, tex: TextureIndex) -> np.void:
    """One closure record: the fields its kind reads. For a Mix the weight stored is the factor f for both closures;
    the kernel uses 1 - f for the first (`first`, kind.z = 1) and f for the second."""
    def node(v: object) -> int:
        return tex(v) if is_texture(v) else TEX_NONE

    kind = kind_of(c.kind)
    r = np.zeros((), L.CLOSURE)
    r["tex"] = TEX_NONE
    r["tex2"] = TEX_NONE
    r["kind"] = (kind.code, 0, int(first), 0)
    for name in kind.fields:
        FIELD_LANES[name](r, getattr(c, name), node)
    r["spec"][3] = constant_float(weight, 0.5)
    r["tex2"][2] = node(weight)
    return r
