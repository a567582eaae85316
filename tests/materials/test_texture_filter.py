"""How camera rays filter images (Settings.texture_filter, render/plan.py texture_full): a still render reads them at
full resolution per sample, so that its mean is the pixel's average of shaded full-resolution samples, as Cycles
converges to; the mip level of the ray cone (animation frames, and the "mip" choice) averages the texels before
shading, which a nonlinear input such as a normal map does not survive.

The scene: a checkerboard of 4 x 4-texel blocks of normals tilted by +-40 degrees towards the tangent, minified 32
times on the square of texture_scenes.py, lit head-on by a sun from the camera. Every full-resolution texel shades
at cos 40 degrees of the flat square's value; Linear blends the colours of neighbouring texel centres, whose mean
shading is integrated below in numpy; a mip texel averages the two tilts to the flat normal."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import ImageTexture, Material, NormalMap, Renderer, Settings

from ..texture_scenes import facing_square

TILT = math.radians(40.0)
SIZE, TEXELS, BLOCK = 16, 512, 4  # 32 x 32 texels per pixel, blocks of 4 x 4
#: the texture repeats SCALE times across the square, so that the pixels' edges fall at every phase of the pattern
#: (all pixels of a still share each sample's jitter)
SCALE = 1.0937


def block_sign(i: np.ndarray) -> np.ndarray:
    """+1 or -1 by the parity of texel i's block along one axis."""
    return np.where((np.floor(i) // BLOCK) % 2 == 0, 1.0, -1.0)


def normal_checker() -> np.ndarray:
    """(TEXELS, TEXELS, 3) Non-Color normal-map colours: tangent-space normals (+-sin, 0, cos) by the checker."""
    i = np.arange(TEXELS)
    sign = np.outer(block_sign(i), block_sign(i))
    img = np.empty((TEXELS, TEXELS, 3), np.float32)
    img[..., 0] = 0.5 + 0.5 * math.sin(TILT) * sign
    img[..., 1] = 0.5
    img[..., 2] = 0.5 + 0.5 * math.cos(TILT)
    return img


def linear_mean_cosine(n: int = 4000) -> float:
    """The mean cosine to the normal of the bilinearly interpolated checker over one period: the checker's sign is
    a product of one sign per axis, so its bilinear interpolation is the product of their linear interpolations
    between texel centres; the tangent component is sin(TILT) times it, the normal one cos(TILT), renormalised."""
    period = 2 * BLOCK
    x = (np.arange(n) + 0.5) / n * period
    centres = np.arange(-1, period + 1) + 0.5
    a = np.interp(x, centres, block_sign(centres))
    g = np.outer(a, a)
    return float(np.mean(math.cos(TILT) / np.sqrt(math.cos(TILT) ** 2 + (math.sin(TILT) * g) ** 2)))


def bumpy(interp: str) -> Material:
    image = ImageTexture(normal_checker(), colorspace="Non-Color", interpolation=interp,
                         mapping=np.diag([SCALE, SCALE, 1.0, 1.0]))
    return Material("bumpy", normal=NormalMap(image))


def still_mean(material: Material, samples: int, **settings) -> np.ndarray:
    s = Settings(method="light_array", **settings)
    return Renderer(facing_square(material, SIZE), s).render_still(0, samples).color[..., :3]


@pytest.mark.parametrize("interp", ["Closest", "Linear"])
def test_a_still_of_a_minified_normal_map_converges_to_full_resolution_shading(device, interp):
    flat = still_mean(Material("flat"), 4)
    assert flat.min() > 0.05 and np.ptp(flat) < 1e-4 * flat.max()  # a uniformly lit square
    mapped = bumpy(interp)
    want = math.cos(TILT) if interp == "Closest" else linear_mean_cosine()
    assert want < 0.9  # what the mip level shades (the flat normal, 1) is far from it
    # Closest: every texel shades alike, so any sample gives the mean; Linear: 64 jittered samples in each pixel
    # of 4.4 x 4.4 periods (the cosine lies between cos 40 degrees and 1)
    samples = 4 if interp == "Closest" else 64
    ratio = still_mean(mapped, samples) / flat
    assert ratio.mean() == pytest.approx(want, abs=3e-3)
    np.testing.assert_allclose(ratio, want, atol=0.03 if interp == "Linear" else 1e-4)  # a pixel: 4.4 periods
    # negative control: the same still read from the ray cone's mip level shades the averaged (flat) normal
    mip = still_mean(mapped, samples, texture_filter="mip") / flat
    assert mip.mean() == pytest.approx(1.0, abs=0.01)
    assert abs(mip.mean() - want) > 0.1


def test_animation_frames_keep_the_mip_level_and_full_reads_full_resolution(device):
    scene = facing_square(bumpy("Closest"), SIZE)
    flat = Renderer(facing_square(Material("flat"), SIZE), Settings(method="light_array")).render_frame(0).color
    frame = Renderer(scene, Settings(method="light_array")).render_frame(0).color
    full = Renderer(scene, Settings(method="light_array", texture_filter="full")).render_frame(0).color
    ratio_frame, ratio_full = frame[..., :3] / flat[..., :3], full[..., :3] / flat[..., :3]
    assert ratio_frame.mean() == pytest.approx(1.0, abs=0.01)  # auto: an animation frame reads the mip level
    np.testing.assert_allclose(ratio_full, math.cos(TILT), atol=1e-4)
