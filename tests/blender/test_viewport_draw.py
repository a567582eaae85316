"""The viewport's drawing code run for real: viewport.draw_frame and view_draw draw into a GPU offscreen of
background bpy (tests/blender/viewport_draw_script.py, in a Python of its own, which gets its GPU context from a
Workbench render: Mesa's llvmpipe through EGL where there is no GPU), and the pixels read back are the frame's.

What bind_display_space_shader binds in Blender 5.0 is the plain image shader: the frame's scene-linear values go
into the 3D view's colour buffer unchanged, and the view transform is applied to that buffer later by Blender.
So the read-back equals the frame itself (to half-float precision, the buffer's format), stretched bilinearly
over the region at a pixel size above 1."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("bpy")

from .test_blender_support import needs_renderer  # noqa: E402

pytestmark = pytest.mark.blender

SCRIPT = Path(__file__).with_name("viewport_draw_script.py")
HALF = 2.0**-10  # relative step of a half float near 1: two roundings (texture, colour buffer) stay below it


def half(a: np.ndarray) -> np.ndarray:
    return a.astype(np.float16).astype(np.float32)


def bilinear_stretch(img: np.ndarray, width: int, height: int) -> np.ndarray:
    """img (h, w, c) drawn over width x height pixels with bilinear filtering and clamped edges, as the GPU
    samples a texture at each pixel's centre."""
    h, w = img.shape[:2]
    x = np.clip((np.arange(width) + 0.5) * w / width - 0.5, 0, w - 1)
    y = np.clip((np.arange(height) + 0.5) * h / height - 0.5, 0, h - 1)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    x1, y1 = np.minimum(x0 + 1, w - 1), np.minimum(y0 + 1, h - 1)
    fx, fy = (x - x0)[None, :, None], (y - y0)[:, None, None]
    top = img[y0][:, x0] * (1 - fx) + img[y0][:, x1] * fx
    bottom = img[y1][:, x0] * (1 - fx) + img[y1][:, x1] * fx
    return top * (1 - fy) + bottom * fy


@pytest.fixture(scope="module")
def drawn(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("viewport_draw") / "drawn.npz"
    env = dict(os.environ)
    proc = subprocess.run([sys.executable, str(SCRIPT), str(out)], capture_output=True, text=True, timeout=900,
                          env=env)
    line = next((ln for ln in proc.stdout.splitlines() if ln.startswith("viewport-draw:")), "")
    if line.startswith("viewport-draw: skip"):
        pytest.skip(line)
    assert proc.returncode == 0 and line.startswith("viewport-draw: ok"), proc.stdout[-3000:] + proc.stderr[-3000:]
    with np.load(out) as data:
        return {k: data[k] for k in data.files}


@needs_renderer
def test_draw_frame_draws_the_frame_as_it_is(drawn):
    frame = drawn["frame1"]
    np.testing.assert_allclose(drawn["same_size"], half(frame), rtol=HALF, atol=1e-6)
    assert drawn["same_size"][..., :3].max() > 3.0  # HDR values are not clamped at 1
    assert bool(drawn["blend_after"])  # the blend state is left as it was found


@needs_renderer
def test_draw_frame_uploads_a_frame_once(drawn):
    # the same frame index again, with other pixels: the texture of the first upload is drawn
    assert bool(drawn["texture_kept"])
    np.testing.assert_array_equal(drawn["same_index"], drawn["same_size"])


@needs_renderer
def test_a_smaller_frame_is_stretched_over_the_region(drawn):
    small = drawn["frame2"]
    assert tuple(drawn["texture_size"]) == (small.shape[1], small.shape[0])
    got = drawn["half_size"]
    want = bilinear_stretch(half(small), got.shape[1], got.shape[0])
    # the GPU's filter weights have 8 bits of sub-texel precision (llvmpipe as GPUs): 1/256 of a neighbour step
    step = np.abs(np.diff(small, axis=0)).max() + np.abs(np.diff(small, axis=1)).max()
    np.testing.assert_allclose(got, want, rtol=HALF, atol=step / 256 + 1e-6)


@needs_renderer
def test_view_draw_draws_the_sessions_newest_frame(drawn):
    frame = drawn["session_frame"]
    assert frame.shape == drawn["view_draw"].shape  # pixel size 1: one frame pixel per region pixel
    assert np.all(np.isfinite(frame)) and frame[..., :3].mean() > 0.01
    np.testing.assert_allclose(drawn["view_draw"], half(frame), rtol=HALF, atol=1e-6)
