"""The transparent part of a surface's terms (shaders.py: Transparent BSDFs, a Principled BSDF's Alpha) -> the
Material's coverage (restircl.materials.alpha): what passes straight through leaves the terms, and the rest is
renormalised by the coverage, since a ray that stops at the surface (with the coverage as its probability) sees
the surface without its transparent part.

Cycles' surface: sum over closures w_i a_i f_i + sum over Transparent BSDFs t_j c_j (pass-through) + emission; with
constant weights the coverage is 1 - sum t_j mean(c_j) - sum w_i (1 - a_i), and each closure's weight becomes
w_i a_i / coverage (a Transparent colour is taken as its mean, with a note where it is not grey). With a texture
(an image's alpha on the Principled Alpha, or as a Mix Shader's factor between a Transparent BSDF and one other
closure) the coverage is that texture (an Invert of it where the Transparent BSDF takes the factor's share)."""

from __future__ import annotations

import dataclasses

from .notes import Notes
from .shaders import Term, Weight


def _constant(v) -> bool:
    return isinstance(v, float | int)


def _mean(colour) -> float:
    return sum(float(c) for c in colour) / 3.0


def split(terms: list[Term], notes: Notes) -> tuple[list[Term], object]:
    """(the terms with the transparent part taken out and renormalised, the coverage: a number or a texture)."""
    out, coverage = _split(terms, notes)
    from restircl.materials.alpha import AlphaError, alpha_source

    try:
        alpha_source(coverage)
    except AlphaError:
        notes.note(f"an alpha driven by a {type(coverage).__name__} node (only a constant or an Image Texture on "
                   "the UV map) is left out: the surface renders opaque")
        return [dataclasses.replace(t, closure=_opaque(t.closure)) if t.closure is not None else t for t in out], 1.0
    return out, coverage


def _split(terms: list[Term], notes: Notes) -> tuple[list[Term], object]:
    clear = [t for t in terms if t.transparent is not None]
    rest = [t for t in terms if t.transparent is None]
    closures = [t for t in rest if t.closure is not None]
    textured = [t for t in closures if not _constant(t.closure.alpha)]
    if not clear and not textured and all(float(t.closure.alpha) >= 1.0 for t in closures):
        return terms, 1.0
    for t in clear:
        if max(t.transparent) - min(t.transparent) > 1e-6:
            notes.note(f"{t.label}: a coloured Transparent BSDF passes light as its mean colour (grey)")
    if not clear and len(textured) == 1 and len(closures) == 1:
        c = closures[0]
        return [dataclasses.replace(c, closure=_opaque(c.closure)), *(t for t in rest if t is not c)], c.closure.alpha
    if any(t.weight.factor is not None for t in clear) or textured:
        return _textured(clear, rest, closures, notes)
    return _constants(clear, rest, closures)


def _opaque(c):
    return dataclasses.replace(c, alpha=1.0)


def _constants(clear: list[Term], rest: list[Term], closures: list[Term]) -> tuple[list[Term], object]:
    through = sum(t.weight.c * _mean(t.transparent) for t in clear)
    through += sum(t.weight.c * (1.0 - float(t.closure.alpha)) for t in closures)
    coverage = min(max(1.0 - through, 0.0), 1.0)
    if coverage <= 0.0:
        return [], 0.0
    out = []
    for t in rest:
        a = float(t.closure.alpha) if t.closure is not None else 1.0
        closure = _opaque(t.closure) if t.closure is not None else None
        out.append(dataclasses.replace(t, weight=t.weight.scaled(a / coverage), closure=closure))
    return out, coverage


def _textured(clear: list[Term], rest: list[Term], closures: list[Term], notes: Notes) -> tuple[list[Term], object]:
    """One Transparent BSDF and one closure under a Mix Shader of a texture factor f: the coverage is the closure's
    share (f, or 1 - f as an Invert)."""
    from restircl import Invert

    if len(clear) == 1 and len(closures) == 1:
        t, c = clear[0], closures[0]
        tw, cw = t.weight, c.weight
        if tw.factor is not None and tw.factor is cw.factor and tw.invert != cw.invert and abs(tw.c - 1) < 1e-9 \
                and abs(cw.c - 1) < 1e-9 and _constant(c.closure.alpha) and float(c.closure.alpha) >= 1.0:
            coverage = cw.factor if not cw.invert else Invert(color=cw.factor, factor=1.0)
            return [dataclasses.replace(x, weight=Weight(1.0)) for x in rest], coverage
    notes.note("a texture-driven transparency of this form (more than one Transparent BSDF or closure under it) "
               "is left out: the surface renders opaque")
    return [dataclasses.replace(t, closure=_opaque(t.closure)) if t.closure is not None else t for t in rest], 1.0
