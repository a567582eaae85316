"""Cryptomatte in Blender (View Layer > Passes > Cryptomatte: Object, Material, Asset, Levels): the toggles set
Settings.cryptomatte_levels, each kind on registers its passes as Cycles names them (<Kind>00, 01, ...: RGBA, two
ranks each), the frame's ranked ids fill them, and the Render Result gets each layer's manifest as metadata
(cryptomatte/<key>/name, hash, conversion, manifest: what the compositor's Cryptomatte node reads)."""

from __future__ import annotations

import numpy as np
from restircl.render.cryptomatte import KINDS, LAYER_SUFFIX, metadata

TOGGLES = {"object": "use_pass_cryptomatte_object", "material": "use_pass_cryptomatte_material",
           "asset": "use_pass_cryptomatte_asset"}


def kinds_on(view_layer) -> list[str]:
    return [k for k in KINDS if getattr(view_layer, TOGGLES[k], False)]


def levels(view_layer) -> int:
    """Settings.cryptomatte_levels for a render of `view_layer`: its Levels where a kind is on, else 0."""
    return int(getattr(view_layer, "pass_cryptomatte_depth", 6)) if kinds_on(view_layer) else 0


def pass_names(kind: str, depth: int) -> list[str]:
    return [f"{LAYER_SUFFIX[kind]}{k:02d}" for k in range((depth + 1) // 2)]


def register_cryptomatte(engine, scene, view_layer) -> None:
    """RenderEngine.update_render_passes: the passes of every kind the view layer has on."""
    for kind in kinds_on(view_layer):
        for name in pass_names(kind, levels(view_layer)):
            engine.register_pass(scene, view_layer, name, 4, "RGBA", "COLOR")


def cryptomatte_data(frame, pass_name: str, height: int, width: int) -> np.ndarray | None:
    """(H, W, 4) float32 of Cryptomatte pass `pass_name` (two ranks: id, coverage, id, coverage), or None."""
    layers = getattr(frame, "cryptomatte", None)
    if not layers:
        return None
    for kind, suffix in LAYER_SUFFIX.items():
        if pass_name.startswith(suffix) and pass_name[len(suffix):].isdigit() and kind in layers:
            k = int(pass_name[len(suffix):])
            arr = layers[kind][..., 4 * k:4 * k + 4]
            if arr.shape != (height, width, 4):
                return None
            return np.ascontiguousarray(arr, dtype=np.float32)
    return None


def add_metadata(result, frame, view_layer) -> None:
    """Each kind's manifest into the Render Result's metadata, under Cycles' keys."""
    names = getattr(frame, "cryptomatte_names", None)
    if not names or result is None or not hasattr(result, "stamp_data_add_field"):
        return
    for kind in kinds_on(view_layer):
        for key, value in metadata(f"{view_layer.name}.{LAYER_SUFFIX[kind]}", names.get(kind, [])).items():
            result.stamp_data_add_field(key, value)
