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


def method_settings(name: str, base: Settings | None, seed: int) -> Settings:
    return Settings(**{**(base.__dict__ if base else {}), **METHODS[name], "seed": seed})
