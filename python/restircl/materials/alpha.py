"""A surface's coverage, Material.alpha: what fraction of the light meeting it the surface takes (its closures and
emission) and what fraction passes straight through, unchanged (a white Transparent BSDF), as Cycles mixes the
Principled BSDF's Alpha and a Mix Shader of a Transparent BSDF with another closure.

Every ray that meets the surface reads the same coverage (camera rays, shadow rays, bounce rays:
opencl/surface/alpha.h), so it comes in the forms that a ray can evaluate from the triangle alone, without the
texture programs of the primary hit:
- a number in [0, 1];
- an Image Texture on the UV map (with a Mapping node or none), its Alpha output (`alpha=True`) or its colour read
  as a number (its grey, as Blender converts a colour linked to a value socket);
- either of those images under an Invert of factor 1 (1 - the image: a Transparent BSDF in the second slot of a
  Mix Shader driven by the image).
"""

from __future__ import annotations

from dataclasses import dataclass

from .material import Material
from .textures import ImageTexture, Input, Invert, is_texture

ALPHA_FORMS = "a number in [0, 1], an Image Texture on UV coordinates, or an Invert (factor 1) of one"


class AlphaError(ValueError):
    """An alpha input of a form a ray cannot evaluate (materials/check.py names the material)."""


@dataclass(frozen=True)
class AlphaSource:
    """A coverage as the rays evaluate it: `constant` where there is no image; else the image's alpha channel
    (`channel` "alpha") or grey ("grey"), 1 minus it with `invert`."""

    constant: float = 1.0
    image: ImageTexture | None = None
    channel: str = "alpha"
    invert: bool = False


def alpha_source(value: Input) -> AlphaSource:
    """The AlphaSource of an alpha input; AlphaError for a form a ray cannot evaluate (ALPHA_FORMS)."""
    invert = False
    if isinstance(value, Invert):
        if is_texture(value.factor) or abs(float(value.factor) - 1.0) > 1e-6:  # type: ignore[arg-type]
            raise AlphaError(f"alpha: an Invert must have factor 1, got {value.factor!r}")
        value, invert = value.color, True
    if isinstance(value, ImageTexture):
        if value.coords != "uv":
            raise AlphaError(f"alpha: an Image Texture must read the UV map, not {value.coords!r} coordinates")
        return AlphaSource(1.0, value, "alpha" if value.alpha else "grey", invert)
    if is_texture(value) or invert:
        raise AlphaError(f"alpha must be {ALPHA_FORMS}, got {type(value).__name__}")
    try:
        a = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise AlphaError(f"alpha must be {ALPHA_FORMS}, got {value!r}") from None
    if not 0.0 <= a <= 1.0:  # NaN fails too
        raise AlphaError(f"alpha must be in [0, 1], got {value!r}")
    return AlphaSource(a)


def is_transparent(m: Material) -> bool:
    """Whether some ray may pass through m: an alpha below 1 or an image-driven one."""
    a = m.alpha
    return is_texture(a) or float(a) < 1.0  # type: ignore[arg-type]
