"""Render Region and Crop to Render Region through bpy: F12 renders only the region's pixels, Blender places them
in the frame (empty elsewhere) or crops to them, they are the pixels the whole frame has there, and the render
takes time in proportion to the region's area."""

from __future__ import annotations

import time

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval.blender_scenes import comparison_scene  # noqa: E402

from .test_blender_support import ensure_registered, needs_renderer, read_exr_passes, render_to  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

# (min x, max x, min y, max y) of the border; at 64 x 48 Blender truncates it to columns 16..47 and rows 4..23
# from the bottom, i.e. rows 24..43 from the top
BORDER = (0.25, 0.75, 0.1, 0.5)
COLS, ROWS = slice(16, 48), slice(24, 44)


def scene(width: int = 64, height: int = 48, samples: int = 4, border=None, crop: bool = False, jitter: bool = True):
    ensure_registered()
    sc = comparison_scene("point", width, height)
    sc.render.engine = "RESTIRCL"
    sc.restircl.samples = samples
    sc.restircl.jitter = jitter
    sc.view_layers[0].use_pass_z = True
    r = sc.render
    if border is not None:
        r.use_border = True
        r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = border
        r.use_crop_to_border = crop
    return sc


def passes(sc, path) -> dict[str, np.ndarray]:
    render_to(sc, path)
    return read_exr_passes(path)


def test_region_renders_only_the_region_where_the_frame_has_it(tmp_path):
    # rays through the pixels' centres: a still's place in its pixel is drawn with the pixel's Sobol point (seeded by
    # its index in the image rendered, here the region), so with jitter the depths agree only to the jitter
    whole = passes(scene(jitter=False), tmp_path / "whole.exr")
    part = passes(scene(border=BORDER, jitter=False), tmp_path / "part.exr")
    rgba = part["Combined"]
    assert rgba.shape == (48, 64, 4)
    inside = np.zeros((48, 64), bool)
    inside[ROWS, COLS] = True
    assert np.all(rgba[~inside] == 0.0), "pixels outside the region were written"
    assert np.all(rgba[inside][:, 3] == 1.0) and rgba[inside][:, :3].mean() > 0.01
    # the same surfaces at the same depths: the region's camera is the whole camera's, in part
    ref, got = whole["Depth"][ROWS, COLS, 0], part["Depth"][ROWS, COLS, 0]
    assert np.allclose(got, ref, rtol=1e-4)


def test_crop_writes_the_region_alone(tmp_path):
    whole = passes(scene(jitter=False), tmp_path / "whole.exr")
    crop = passes(scene(border=BORDER, crop=True, jitter=False), tmp_path / "crop.exr")
    assert crop["Combined"].shape == (20, 32, 4)
    assert np.allclose(crop["Depth"][..., 0], whole["Depth"][ROWS, COLS, 0], rtol=1e-4)


def test_a_border_over_the_whole_frame_is_the_whole_frame(tmp_path):
    whole = passes(scene(), tmp_path / "whole.exr")
    full = passes(scene(border=(0.0, 1.0, 0.0, 1.0), crop=True), tmp_path / "full.exr")
    assert np.array_equal(full["Combined"], whole["Combined"])


def render_seconds(sc, path, repeats: int = 2) -> float:
    """The fastest of `repeats` F12 renders (the first builds the renderer: its kernels come from the cache)."""
    best = float("inf")
    for k in range(repeats + 1):
        t0 = time.perf_counter()
        render_to(sc, path)
        if k:
            best = min(best, time.perf_counter() - t0)
    return best


@pytest.mark.slow
def test_time_follows_the_area(tmp_path):
    """A quarter of the frame renders in about a quarter of the time (the export and the write of the result
    are the rest)."""
    whole = render_seconds(scene(320, 240, 256), tmp_path / "whole.exr")
    part = render_seconds(scene(320, 240, 256, border=(0.25, 0.75, 0.25, 0.75)), tmp_path / "part.exr")
    print(f"render region: whole {whole:.2f} s, a quarter {part:.2f} s, ratio {part / whole:.2f}")
    assert part / whole < 0.4
