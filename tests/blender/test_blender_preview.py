"""Material previews (bl_use_preview) rendered by restircl, through Blender's own preview job: in background bpy,
ID.asset_generate_preview renders a material's icon preview (128x128, Blender's preview scene: the sphere, two
area lights, the checker floor, the preview world, film transparent) on a job thread, calling the engine's render
with is_preview set. The icon must be finite, use preview_samples of the user's scene, and agree in level on the
sphere with the icon Cycles renders of the same material.

The floor is left out of the comparison: its material (FloorHidden) is transparent to camera rays in Cycles, and
restircl does not render transparency (it warns), so our floor is seen where Cycles' alpha is 0. Measured on the
sphere (Cycles' alpha 1) for the material below: the mean display value per channel within 0.2% of Cycles'
(Blender 5.0, preview_samples 16); the bound is ten times that."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered, needs_renderer  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]
BOUND = 0.02  # relative difference of the sphere's mean display value per channel


@pytest.fixture(scope="module")
def previews():
    ensure_registered()
    scenes.new_scene(32, 32, engine="RESTIRCL")
    mat = scenes.diffuse_material("PreviewOrange", (0.8, 0.3, 0.1))
    props = bpy.context.scene.restircl
    props.preview_samples = 16
    ours = scenes.preview_icon(mat, "RESTIRCL")
    props.preview_samples = 1
    one = scenes.preview_icon(mat, "RESTIRCL")
    props.preview_samples = 16
    cycles = scenes.preview_icon(mat, "CYCLES")
    bpy.context.scene.render.engine = "RESTIRCL"
    return ours, one, cycles


def test_preview_is_rendered_by_us_and_finite(previews):
    ours, _one, _cycles = previews
    assert ours.shape == (128, 128, 4) and np.all(np.isfinite(ours))
    centre = ours[56:72, 56:72, :3].mean((0, 1))  # the lit sphere fills the middle
    assert centre.min() > 0.2 and centre[0] > centre[2]  # orange, not black or the world


def test_preview_samples_setting_reaches_the_preview(previews):
    ours, one, _cycles = previews
    sphere = ours[40:88, 40:88, :3]
    assert not np.array_equal(sphere, one[40:88, 40:88, :3])  # 1 sample is another (noisier) image
    # 1 sample is noisier: its pixel-to-pixel differences are larger than those of 16
    rough = [float(np.abs(np.diff(img[40:88, 40:88, :3], axis=1)).mean()) for img in (ours, one)]
    assert rough[1] > rough[0]


def test_preview_agrees_with_cycles_on_the_sphere(previews):
    ours, _one, cycles = previews
    sphere = cycles[..., 3] > 0.99
    assert sphere.mean() > 0.3  # the sphere is in view
    rel = ours[sphere, :3].mean(0) / cycles[sphere, :3].mean(0) - 1.0
    assert np.all(np.abs(rel) < BOUND), rel
