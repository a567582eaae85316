"""TAA quality (opencl/taa/taa.cl): a still camera keeps converging; Catmull-Rom history under a panning camera keeps a
fine texture sharper than bilinear (which blurs a little at every reprojection); velocity dilation lets the
edge pixels of a moving object follow it. Each against the converged image of every frame."""

import numpy as np
import pytest
from restircl import Camera, CheckerTexture, Light, Material, Mesh, Renderer, Scene, Settings, look_at, scenes

from ..helpers import rel_mse

W, H = 48, 32


def _checker_scene(frames: int, speed: float, box_speed: float = 0.0) -> Scene:
    """A floor of fine checker squares under a sun; the camera pans `speed` m a frame; a box moves `box_speed`."""
    fv, ft = scenes.quad(12, 12)
    bv, bt = scenes.box((0.6, 0.6, 0.6))
    materials = [Material("floor", CheckerTexture(color1=(0.9, 0.9, 0.9), color2=(0.05, 0.05, 0.05), scale=8.0,
                                                 coords="object")),
                 Material("box", (0.8, 0.2, 0.1))]
    box_t = np.array([np.eye(4) for _ in range(frames)])
    box_t[:, 0, 3] = -0.6 + box_speed * np.arange(frames)
    box_t[:, 2, 3] = 0.3
    meshes = [Mesh("floor", fv, ft, 0), Mesh("box", bv, bt, 1, transforms=box_t)]
    sun = Light("sun", "sun", (1, 1, 1), 3.0, look_at((1, -1, 3), (0, 0, 0)))
    eyes = [look_at((-0.4 + speed * f, -2.5, 1.6), (-0.4 + speed * f, 0.5, 0.0)) for f in range(frames)]
    return Scene(meshes, materials, [sun], Camera(np.array(eyes), W, H, lens=35.0), name="checker_pan")


def _references(scene: Scene, device) -> list[np.ndarray]:
    r = Renderer(scene, Settings(method="ris", taa=False, seed=1), device)
    return [r.render_still(f, 64).color for f in range(scene.frames)]


def _taa_error(scene: Scene, refs, first: int, device, **kw) -> float:
    r = Renderer(scene, Settings(method="ris", seed=2, **kw), device)
    out = [r.render_frame(f, aovs=False).color for f in range(scene.frames)]
    return float(np.mean([rel_mse(out[f], refs[f]) for f in range(first, scene.frames)]))


def test_a_still_camera_keeps_converging(device):
    """Frames of a still camera: the blend is 1/n up to max_history, so the error of frame 64 is about a quarter of
    frame 16's (variance ~ 1/n); with the old floor a = alpha_min = 0.1 both would sit near the same 0.053
    sigma^2. Bound: below 0.6x."""
    sc = scenes.many_lights(32, 18, frames=1)
    ref = Renderer(sc, Settings(method="ris", candidates=16, seed=9), device).render_still(0, 512).color
    r = Renderer(sc, Settings(method="ris", seed=4), device)
    errs = {}
    for n in range(1, 65):
        f = r.render_frame(0, aovs=False)
        if n in (16, 64):
            errs[n] = rel_mse(f.color, ref)
    assert errs[64] < 0.6 * errs[16], errs


@pytest.fixture(scope="module")
def pan(device):
    scene = _checker_scene(16, 0.013)
    return scene, _references(scene, device)


def test_catmull_rom_history_is_sharper_than_bilinear_under_a_pan(pan, device):
    scene, refs = pan
    bil = _taa_error(scene, refs, 6, device, taa_filter="bilinear")
    cr = _taa_error(scene, refs, 6, device, taa_filter="catmull_rom")
    print(f"pan over a checker floor, TAA relMSE frames 6-15: bilinear {bil:.4f}, Catmull-Rom {cr:.4f}")
    assert cr < 0.9 * bil, (cr, bil)


def test_velocity_dilation_keeps_a_moving_edge_and_is_finite(device):
    scene = _checker_scene(14, 0.0, box_speed=0.05)
    refs = _references(scene, device)
    plain = _taa_error(scene, refs, 4, device)
    dil = _taa_error(scene, refs, 4, device, taa_dilation=True)
    print(f"moving box, TAA relMSE frames 4-13: plain {plain:.4f}, dilated {dil:.4f}")
    assert np.isfinite(dil) and dil <= 1.1 * plain, (dil, plain)
