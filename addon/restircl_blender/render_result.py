"""A restircl.Frame into Blender's Render Result: the passes the result has, each converted once, rows flipped
(the Frame's rows are top first, Blender's bottom first), misses given Blender's values."""

from __future__ import annotations

import numpy as np
from restircl.render.passes import PASSES, blender_name

from .compat import blender_version
from .cryptomatte import add_metadata, cryptomatte_data, kinds_on
from .light_groups import light_group_data, light_group_names
from .passes import pass_on


def aovs_needed(view_layer, film_transparent: bool) -> bool:
    """Whether a frame must read back its G-buffer and light passes: only for a pass the view layer has on, or for
    the alpha of a transparent film (from the depth)."""
    read = [p for p in PASSES[1:] if p.attr in ("depth", "normal", "vector", "albedo", "object_index", "material_index")
            or p.requires == "light_passes"]
    return (film_transparent or any(pass_on(view_layer, p) for p in read) or bool(light_group_names(view_layer))
            or bool(kinds_on(view_layer)))


def write_result(engine, frame, width: int, height: int, view_layer, film_transparent: bool) -> None:
    """Copy a restircl.Frame (rows top first) into the Render Result (rows bottom first): only the passes the
    result has, each converted once."""
    # the metadata goes to the whole render's result (the one saved), not to this layer's part of it
    add_metadata(engine.get_result() if hasattr(engine, "get_result") else None, frame, view_layer)
    result = engine.begin_result(0, 0, width, height, layer=view_layer.name)
    try:
        version = blender_version()
        by_name = {blender_name(p, version): p for p in PASSES}
        for rp in result.layers[0].passes:
            p = by_name.get(rp.name)
            if p is None:
                data = light_group_data(frame, rp.name, height, width)
                if data is None:
                    data = cryptomatte_data(frame, rp.name, height, width)
            else:
                data = _combined(frame, height, width, film_transparent) if p is PASSES[0] else \
                    _pass_data(frame, p, height, width)
            if data is None or data.shape[2] != rp.channels:
                continue
            flipped = np.ascontiguousarray(data[::-1].reshape(width * height, rp.channels))
            if not np.all(np.isfinite(flipped)):
                flipped = np.nan_to_num(flipped, nan=0.0, posinf=0.0, neginf=0.0)
            _set_rect(rp, flipped)
    finally:
        engine.end_result(result)


def _pass_data(frame, p, height: int, width: int) -> np.ndarray | None:
    """A pass of a restircl.Frame as (H, W, C) float32, with Blender's value where nothing is hit."""
    arr = getattr(frame, p.attr, None)
    if arr is None:
        return None
    arr = np.asarray(arr, dtype=np.float32)
    if arr.ndim == 2:
        arr = arr[..., None]
    if arr.shape[:2] != (height, width):
        return None
    if p.miss is not None:
        arr = np.where(np.isfinite(arr), arr, np.float32(p.miss)).astype(np.float32)
    return arr


def _combined(frame, height: int, width: int, film_transparent: bool) -> np.ndarray | None:
    """RGBA of the image; with a transparent film, alpha 0 where the camera ray hits nothing (in a scene with
    transparent surfaces, the share of the samples whose camera ray stopped at a surface)."""
    colour = _pass_data(frame, PASSES[0], height, width)
    if colour is None:
        return None
    colour = colour.copy()
    if colour.shape[2] == 3:
        colour = np.concatenate([colour, np.ones_like(colour[..., :1])], axis=2)
    depth = getattr(frame, "depth", None)
    if depth is not None and np.shape(depth)[:2] != (height, width):
        depth = None
    coverage = getattr(frame, "coverage", None)
    if film_transparent and coverage is not None and np.shape(coverage)[:2] == (height, width):
        colour[..., 3] = coverage  # the mean over the samples: a surface's coverage where rays pass through it
    elif film_transparent and depth is not None:
        colour[..., 3] = np.isfinite(np.asarray(depth, dtype=np.float32)).reshape(height, width)
    elif not film_transparent:
        colour[..., 3] = 1.0
    shares = getattr(frame, "holdout_shares", None)
    holdout = getattr(frame, "holdout", None)
    if shares is not None and np.shape(shares) == (height, width, 2):  # a still's: the share each sample saw
        colour[..., 3] = _covered_alpha(colour[..., 3], np.asarray(shares, np.float32), film_transparent,
                                        coverage is not None)
    elif holdout is not None and np.shape(holdout) == (height, width):  # a hole, film or not (as Cycles)
        colour[np.asarray(holdout, bool)] = 0.0
    return colour


def _covered_alpha(alpha: np.ndarray, shares: np.ndarray, film_transparent: bool, has_coverage: bool) -> np.ndarray:
    """The film's alpha of a still, as Cycles': the share of the pixel that neither a holdout nor (on a transparent
    film) the world covers, antialiased at the edges rather than the last sample's 0 or 1. The colour needs nothing:
    its samples that met the holdout are 0. The coverage of a transparent scene's film already counts both as 0."""
    if film_transparent and has_coverage:
        return alpha
    seen = 1.0 - shares[..., 0] - (shares[..., 1] if film_transparent else 0.0)
    return np.clip(seen, 0.0, 1.0).astype(np.float32)


def _set_rect(render_pass, pixels: np.ndarray) -> None:
    """RenderPass.rect from (pixels, channels) float32. foreach_set takes the buffer whole; assigning the array
    (`rect = pixels`) took 80-150 ms per pass of 192x108 against 0.1 ms (tools/experiments/bench_write_result.py,
    docs/measurements/benchmarks.md)."""
    try:
        render_pass.rect.foreach_set(pixels.reshape(-1))
    except (AttributeError, TypeError):  # a Blender without foreach_set on this array
        render_pass.rect = pixels
