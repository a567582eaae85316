"""The methods `restircl report` compares, as Settings overrides."""

from __future__ import annotations

from ...settings.table import Settings

# name -> Settings overrides
METHODS: dict[str, dict] = {
    "uniform": dict(method="uniform"),
    "light_array": dict(method="light_array"),
    "ris": dict(method="ris"),
    "restir_temporal": dict(method="restir", spatial=False),
    "restir_spatial": dict(method="restir", temporal=False),
    "restir": dict(method="restir"),
    "restir_temporal_biased": dict(method="restir", spatial=False, bias_correction="none"),
    "restir_spatial_biased": dict(method="restir", temporal=False, bias_correction="none"),
    "restir_biased": dict(method="restir", bias_correction="none"),
    # BSDF-sampled candidates forced on or off (the plain names use the default, "auto": on for glossy scenes)
    "ris_bsdf": dict(method="ris", bsdf_sampling="on"),
    "ris_no_bsdf": dict(method="ris", bsdf_sampling="off"),
    "restir_bsdf": dict(method="restir", bsdf_sampling="on"),
    "restir_no_bsdf": dict(method="restir", bsdf_sampling="off"),
    # the bounced light (with Max Bounces > 0 in the base settings) reused by ReSTIR GI, or by paths alone
    "restir_gi": dict(method="restir", gi_reuse=True),
    "restir_paths": dict(method="restir", gi_reuse=False),
}


def _value(text: str, default: object) -> object:
    """A setting's value written on the command line, as the type of its default."""
    if isinstance(default, bool):
        if text.lower() not in ("true", "false", "1", "0", "on", "off"):
            raise ValueError(f"not a boolean: {text!r}")
        return text.lower() in ("true", "1", "on")
    if isinstance(default, int):
        return int(text)
    if isinstance(default, float):
        return float(text)
    return text


def method_overrides(name: str) -> dict:
    """The Settings overrides of a method name: one of METHODS, or one of them with settings changed, written
    `base+key=value+key=value` (e.g. `restir+m_cap=5+candidates=16`), so that a report compares variants of a
    method side by side in one run."""
    head, *parts = name.split("+")
    if head not in METHODS:
        raise ValueError(f"unknown method {head!r}; choose from {', '.join(METHODS)}")
    out = dict(METHODS[head])
    defaults = Settings()
    for part in parts:
        key, sep, text = part.partition("=")
        if not sep or not hasattr(defaults, key):
            raise ValueError(f"{name!r}: {part!r} is not key=value of a setting")
        out[key] = _value(text, getattr(defaults, key))
    return out


def method_settings(name: str, base: Settings | None, seed: int) -> Settings:
    return Settings(**{**(base.__dict__ if base else {}), **method_overrides(name), "seed": seed})
