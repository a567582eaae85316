"""Blender's Light Paths: where the scene has Cycles' settings (`scene.cycles`, present while the Cycles add-on is
enabled, as in every default Blender), restircl takes its bounces, clamping and light threshold from them, so that
a scene renders with the same Light Paths in both engines and the user sets them once; without Cycles they are
restircl's own settings (scene.restircl, from the settings table).

This mapping is the one place that reads them: properties.py's `settings_kwargs` (the Settings of F12 and animation
renders, the viewport and the material previews, and the keys their sessions are compared by) and the engine's
report (`warnings`). Nothing here raises: a value restircl does not accept is moved into its range, with a warning.
Every property is read with getattr and a default, so a release whose Cycles lacks one renders with restircl's own.
"""

from __future__ import annotations

import math
from typing import Any

from restircl import Settings
from restircl.settings.spec import Declared, declared

# restircl setting <- the Cycles property it is read from (scene.cycles.<name>)
FROM_CYCLES = (
    ("max_bounces", "max_bounces"),
    ("diffuse_bounces", "diffuse_bounces"),
    ("glossy_bounces", "glossy_bounces"),
    ("transmission_bounces", "transmission_bounces"),
    ("min_light_bounces", "min_light_bounces"),
    ("clamp_direct", "sample_clamp_direct"),
    ("clamp_indirect", "sample_clamp_indirect"),
    ("light_threshold", "light_sampling_threshold"),
    ("transparent_max_bounces", "transparent_max_bounces"),
)
# Cycles' Light Paths that restircl has no counterpart for yet: property, its label, and Cycles' default (used where
# the property's own RNA default cannot be read); a value other than the default is reported, not applied
NOT_APPLIED = (
    ("volume_bounces", "Volume bounces", 0),
)
_DECLARED = {d.name: d for d in declared(Settings)}


def cycles_of(scene: Any) -> Any | None:
    """Cycles' settings of the scene, or None without the Cycles add-on."""
    return getattr(scene, "cycles", None)


def read(scene: Any) -> tuple[dict[str, Any], list[str]]:
    """The Light Paths settings of restircl.Settings read from Cycles' settings of `scene` (empty without them:
    scene.restircl's own apply) and the warnings about them: values moved into restircl's range, and Light Paths
    set away from Cycles' default that restircl does not apply yet."""
    cycles = cycles_of(scene)
    if cycles is None:
        return {}, []
    values: dict[str, Any] = {}
    messages: list[str] = []
    for name, prop in FROM_CYCLES:
        d = _DECLARED[name]
        value = getattr(cycles, prop, None)
        if value is None:  # not in this release's Cycles: restircl's own setting applies
            continue
        if name == "light_threshold" and bool(getattr(cycles, "use_light_tree", False)):
            value = 0.0  # Cycles applies its light threshold only without its light tree
        fitted = fit(d, value)
        if fitted != value:
            messages.append(f"Light Paths: Cycles' {prop} = {value!r} is outside what restircl accepts "
                            f"({d.spec.range.text() if d.spec.range else d.kind.__name__}); {fitted!r} is used")
        values[name] = fitted
    for prop, label, fallback in NOT_APPLIED:
        value = getattr(cycles, prop, None)
        if value is not None and value != cycles_default(cycles, prop, fallback):
            messages.append(f"Light Paths: {label} ({value:g}) is not applied yet")
    return values, messages


def fit(d: Declared, value: Any) -> Any:
    """`value` as setting `d` takes it: of its type, moved to the nearest end of its range (NaN, or an infinity the
    setting cannot hold, gives the setting's default)."""
    r = d.spec.range
    try:
        number = float(value)
    except (TypeError, ValueError):
        return d.default
    if math.isnan(number):
        return d.default
    if r is not None:
        lo, hi = r.lowest(), r.highest()
        number = number if lo is None else max(number, float(lo))
        number = number if hi is None else min(number, float(hi))
    if not math.isfinite(number) and (d.kind is int or r is None or r.finite):
        return d.default
    fitted = int(round(number)) if d.kind is int else float(number)
    return fitted if r is None or r.contains(fitted) else d.default


def cycles_default(cycles: Any, prop: str, fallback: Any) -> Any:
    """The default of Cycles' property `prop` as its RNA declares it, else `fallback`."""
    rna = getattr(getattr(cycles, "bl_rna", None), "properties", None)
    try:
        return rna[prop].default if rna is not None else fallback
    except (KeyError, AttributeError):
        return fallback
