"""Thin Film (Blender 4.2+: the Principled, Glass and Metallic BSDFs' Thin Film Thickness and IOR): a dielectric
coating whose interference colours the Fresnel of every specular part of the closure (opencl/bsdf/thin_film.h). A
thickness of at most CUTOFF nm is no film, as in Cycles: such a closure compiles and renders as one without it."""

from __future__ import annotations

from typing import Protocol

CUTOFF = 0.1  # nm (THIN_FILM_CUTOFF on the device)
DEFAULT_IOR = 1.33  # Blender's default Thin Film IOR (a soap film)


class Filmed(Protocol):
    thin_film_thickness: float


def has_film(c: Filmed) -> bool:
    """Whether closure c (a Material of a kind that reads the film) has a film."""
    return float(c.thin_film_thickness) > CUTOFF
