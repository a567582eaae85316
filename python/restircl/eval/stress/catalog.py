"""Every case of the stress suite by name (eval/stress/cases.py: direct light; contact.py: receivers touching emitters;
bounces.py: light that bounces; glass.py: glass; transparency.py: transparent surfaces)."""

from __future__ import annotations

from collections.abc import Callable

from . import bounces, glass, transparency
from .cases import (
    Case,
    all_behind,
    area_extremes,
    degenerate,
    grazing,
    long_animation,
    million_lights,
    offset,
    power_span,
    switch_off,
    teleport,
    teleport_cut,
    touching,
)
from .contact import contact

CASES: dict[str, Callable[[bool], Case]] = {
    f.__name__ if f.__name__ != "offset" else "offset_1e5": f
    for f in (power_span, million_lights, area_extremes, touching, grazing, contact, offset, degenerate, all_behind,
              teleport_cut, teleport, switch_off, long_animation, bounces.mirror_room, bounces.hidden_emitter,
              bounces.thousand_bounces, bounces.black_world, glass.nested_glass, glass.total_internal_reflection,
              glass.ior_one, glass.ior_hundred, transparency.alpha_zero, transparency.stacked_cards)
}


def cases(full: bool = False, names: list[str] | None = None) -> list[Case]:
    chosen = names or list(CASES)
    unknown = [n for n in chosen if n not in CASES]
    if unknown:
        raise ValueError(f"unknown stress cases {unknown}; cases: {', '.join(CASES)}")
    return [CASES[n](full) for n in chosen]

