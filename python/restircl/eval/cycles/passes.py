"""Cycles' render passes through bpy (the agreement tests of the light passes): one Cycles render with the view
layer's toggles of the given passes on, read back from a multilayer EXR by the passes' Blender names."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from ...render.passes import PASSES, Pass, blender_name
from .bridge import _bpy, direct_only, exr_output, light_paths


def _channels(path: Path) -> dict[str, np.ndarray]:
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as f:
        return {name: np.asarray(ch.pixels, np.float32) for part in f.parts for name, ch in part.channels.items()}


def _pass_image(chans: dict[str, np.ndarray], names: tuple[str, ...]) -> np.ndarray:
    """The (H, W, 3) image of the pass called one of `names` in the EXR's channels (ViewLayer.<name>.R, ...)."""
    for name in names:
        keys = [next((k for k in chans if k.endswith(f"{name}.{c}")), None) for c in "RGB"]
        if all(k is not None for k in keys):
            return np.stack([chans[k] for k in keys if k is not None], axis=-1)
    raise KeyError(f"no pass {names} among {sorted(chans)}")


def render_passes(sc, attrs: tuple[str, ...], samples: int, seed: int = 0, paths=None) -> dict[str, np.ndarray]:
    """Render the bpy scene `sc` with Cycles (bridge.direct_only's settings, the Light Paths of restircl Settings
    `paths`) and return the passes of render/passes.py named by their Frame fields `attrs`, and "color" (the
    Combined pass's RGB), as (H, W, 3) float32, rows top first."""
    bpy = _bpy()
    direct_only(sc, samples=samples, seed=seed)
    if paths is not None:
        light_paths(sc, paths)
    layer = sc.view_layers[0]
    chosen: list[Pass] = [p for p in PASSES if p.attr in attrs]
    for p in chosen:
        assert p.blender_toggle is not None and "." not in p.blender_toggle, p.attr
        setattr(layer, p.blender_toggle, True)
    exr_output(sc, multilayer=True)
    with tempfile.TemporaryDirectory() as tmp:
        sc.render.filepath = str(Path(tmp) / "passes.exr")
        bpy.ops.render.render(write_still=True, scene=sc.name)
        chans = _channels(Path(tmp) / "passes.exr")
    out = {"color": _pass_image(chans, ("Combined",))}
    version = tuple(bpy.app.version)
    for p in chosen:
        out[p.attr] = _pass_image(chans, (blender_name(p, version), p.blender, p.exr_layer))
    return out
