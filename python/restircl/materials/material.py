"""Materials as Blender's shader nodes define them: the Principled BSDF (and the Diffuse and Glossy BSDFs as
special cases), mixed or added by Mix Shader / Add Shader, with a constant or a texture node
(restircl.materials.textures) on any input.

A Material with `layers` empty is one closure of `kind`, a name from restircl.materials.closures (registry.py);
each kind's module says which shader node it models and which of the fields it reads, and the kind ignores the
others: "principled" (the Principled BSDF; `albedo` is its Base Color), "diffuse" (the Diffuse BSDF), "glossy" (the
Glossy BSDF), "glass" (the Glass BSDF: `albedo` its Color, `roughness`, `ior`), "refraction" (the Refraction
BSDF, the same fields); a Principled BSDF's `transmission` is its Transmission Weight, `thin_wall` its Thin Wall
(Blender 5.3: the transmission is an infinitely thin sheet, opencl/bsdf/closures/thin_wall.h); the Principled and
Glass kinds read `thin_film_thickness` (nm) and `thin_film_ior`, Blender's Thin Film (materials/thin_film.py). The
default is a
Principled BSDF without a specular layer (`specular`, the Specular IOR Level, 0: Blender's default is 0.5 and the add-on
exports it as it is), the plain diffuse albedo it always was.
A Material with `layers` [a, b] (Materials without layers of their own; at most MAX_LAYERS) is their weighted sum:
Mix Shader when `mix` is set, (1 - mix) a + mix b, with `mix` a constant or a texture; Add Shader, a + b, when
`mix` is None. Its own closure fields are then unused. Emission (emission * emission_strength) belongs to the
Material itself, not to a layer.
`alpha` is the surface's coverage (the Principled BSDF's Alpha, or the share of a Mix Shader that is not a
Transparent BSDF): the surface is alpha x (its closures and emission) + (1 - alpha) x a white Transparent BSDF, as
Cycles mixes them; a constant, or an image's alpha or grey (materials/alpha.py says which forms).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import thin_film
from .closures.registry import kind_of
from .textures import Input

DISTRIBUTIONS = ("multi_ggx", "ggx")
MAX_LAYERS = 2
# the closure inputs that may hold a texture node, by field name (normal: a NormalMap); the emission may too
TEXTURABLE = ("albedo", "metallic", "roughness", "specular", "specular_tint", "normal")


@dataclass
class Material:
    name: str = "default"
    albedo: Input = (0.8, 0.8, 0.8)  # Base Color / Color
    emission: Input = (0.0, 0.0, 0.0)  # colour
    emission_strength: float = 0.0
    kind: str = "principled"
    metallic: Input = 0.0
    roughness: Input = 0.5
    ior: float = 1.5
    specular: Input = 0.0  # Specular IOR Level (0.5: the IOR's own reflectance; 0: none)
    specular_tint: Input = (1.0, 1.0, 1.0)
    distribution: str = "multi_ggx"
    normal: Input | None = None  # a NormalMap node, or None for the mesh's shading normal
    layers: list[Material] = field(default_factory=list)
    mix: Input | None = None
    alpha: Input = 1.0  # coverage: 1 opaque, 0 fully transparent (materials/alpha.py)
    pass_index: int = 0  # Material > Settings > Pass Index: the Material Index pass (render/index_passes.py)
    transmission: float = 0.0  # the Principled BSDF's Transmission Weight, in [0, 1]
    thin_wall: bool = False  # the Principled BSDF's Thin Wall (Blender 5.3): its transmission is a thin sheet
    thin_film_thickness: float = 0.0  # Thin Film Thickness (nm; <= materials/thin_film.py CUTOFF: no film)
    thin_film_ior: float = thin_film.DEFAULT_IOR  # Thin Film IOR

    @property
    def radiance(self) -> np.ndarray:
        """Emitted radiance of a constant emission colour; a textured emission reports its (1, 1, 1) bound."""
        col = self.emission if isinstance(self.emission, tuple | list | np.ndarray) else (1.0, 1.0, 1.0)
        return np.asarray(col, dtype=np.float64) * float(self.emission_strength)

    @property
    def is_emissive(self) -> bool:
        return bool(np.any(self.radiance > 0))

    @classmethod
    def mixed(cls, a: Material, b: Material, factor: Input = 0.5, name: str = "mix") -> Material:
        """Mix Shader: (1 - factor) a + factor b."""
        return cls(name=name, layers=[a, b], mix=factor)

    @classmethod
    def added(cls, a: Material, b: Material, name: str = "add") -> Material:
        """Add Shader: a + b."""
        return cls(name=name, layers=[a, b])


def material_inputs(m: Material) -> list[object]:
    """Every input of m that is read and may hold a texture node: the fields its closures' kinds read, its emission
    and the Mix factor."""
    out = [getattr(c, f) for c in (m.layers or [m]) for f in TEXTURABLE if f in kind_of(c.kind).fields]
    return [*out, m.emission, m.mix]
