"""The weighted terms of a shader graph (shaders.py) -> one restircl.Material: at most MAX_LAYERS closures, as
one closure, a Mix Shader ((1 - f) a + f b) or an Add Shader (a + b), and the emission summed.

A weight that neither form holds is folded into the closure's colour where the closure is linear in it (a diffuse
or a Glossy BSDF of a constant colour, a Principled BSDF without a specular layer); otherwise the weights are
renormalised, with a note."""

from __future__ import annotations

import dataclasses

import numpy as np

from .notes import Notes
from .shaders import Term, Weight
from .transparency import split

BLACK = (0.0, 0.0, 0.0)


def _max_layers() -> int:
    from restircl.materials.material import MAX_LAYERS

    return MAX_LAYERS


def _constant(v) -> bool:
    return isinstance(v, tuple | float | int)


def _foldable(c) -> bool:
    if not _constant(c.albedo):
        return False
    if c.kind in ("diffuse", "glossy"):
        return True
    return _constant(c.metallic) and _constant(c.specular) and float(c.metallic) == 0 and float(c.specular) == 0


def _fold(c, k: float):
    return dataclasses.replace(c, albedo=tuple(float(a) * k for a in c.albedo))


def _black():
    import restircl

    return restircl.Material(name="black", kind="diffuse", albedo=BLACK)


def _typical(w: Weight) -> float:
    return w.c * (0.5 if w.factor is not None else 1.0)


def _one(c, w: Weight, notes: Notes):
    """One closure of weight w: itself, folded, or mixed with black."""
    import restircl

    if w.factor is None:
        if abs(w.c - 1.0) < 1e-9:
            return c
        if _foldable(c):
            return _fold(c, w.c)
        if w.c < 1.0:
            return restircl.Material.mixed(c, _black(), 1.0 - w.c)
        notes.note(f"a closure weighted {w.c:g} (more than 1) is rendered with weight 1")
        return c
    if abs(w.c - 1.0) > 1e-9:
        notes.note("a Mix Shader's texture factor under a constant one: the constant is left out")
    return restircl.Material.mixed(c, _black(), w.factor) if w.invert else restircl.Material.mixed(_black(), c,
                                                                                                   w.factor)


def _two(a, wa: Weight, b, wb: Weight, notes: Notes):
    import restircl

    if wa.factor is not None or wb.factor is not None:
        if wa.factor is wb.factor and wa.invert != wb.invert and abs(wa.c - 1) < 1e-9 and abs(wb.c - 1) < 1e-9:
            return restircl.Material.mixed(a, b, wa.factor) if wa.invert else restircl.Material.mixed(b, a, wa.factor)
        notes.note("texture-driven Mix Shader factors that do not sum to one are taken as 0.5")
        wa, wb = Weight(_typical(wa)), Weight(_typical(wb))
    if abs(wa.c - 1) < 1e-9 and abs(wb.c - 1) < 1e-9:
        return restircl.Material.added(a, b)
    total = wa.c + wb.c
    if abs(total - 1) < 1e-9:
        return restircl.Material.mixed(a, b, wb.c)
    if _foldable(a) and _foldable(b):
        return restircl.Material.added(_fold(a, wa.c), _fold(b, wb.c))
    notes.note(f"closure weights {wa.c:g} and {wb.c:g} are renormalised to sum to one")
    return restircl.Material.mixed(a, b, wb.c / total if total > 0 else 0.5)


def _emission(terms: list[Term], notes: Notes) -> tuple[object, float]:
    """(colour, strength) of the emission terms summed."""
    total = np.zeros(3)
    textured = None
    for t in terms:
        c = t.weight.c
        if t.weight.factor is not None:
            notes.note(f"{t.label}: its texture-driven Mix Shader factor is taken as 0.5 for the emission")
            c *= 0.5
        if isinstance(t.emission, tuple):
            total += np.asarray(t.emission, dtype=np.float64) * t.strength * c
        elif textured is None:
            textured = (t.emission, t.strength * c)
        else:
            notes.note(f"{t.label}: a second textured emission is left out")
    if textured is not None:
        if np.any(total > 0):
            notes.note("constant emission next to a textured one is left out")
        return textured[0], max(float(textured[1]), 0.0)
    total = np.maximum(total, 0.0)
    strength = float(total.max())
    if strength <= 0:
        return BLACK, 0.0
    return tuple(float(v / strength) for v in total), strength


def assemble(name: str, terms: list[Term], notes: Notes):
    """One Material named `name` from the terms of its surface."""
    terms, coverage = split(terms, notes)
    closures = [t for t in terms if t.closure is not None]
    emitters = [t for t in terms if t.emission is not None]
    limit = _max_layers()
    if len(closures) > limit:
        order = sorted(range(len(closures)), key=lambda i: -_typical(closures[i].weight))
        keep = sorted(order[:limit])
        notes.dropped.extend(closures[i].label for i in order[limit:])
        closures = [closures[i] for i in keep]
    if not closures:
        m = _black()
    elif len(closures) == 1:
        m = _one(closures[0].closure, closures[0].weight, notes)
    else:
        m = _two(closures[0].closure, closures[0].weight, closures[1].closure, closures[1].weight, notes)
    colour, strength = _emission(emitters, notes)
    return dataclasses.replace(m, name=name, emission=colour, emission_strength=strength, alpha=coverage)
