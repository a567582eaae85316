"""Shadow rays through a smooth thin wall (opencl/bvh/thin_wall_shadow.h): a floor lit by a point light 2 m above it,
straight above the pixel looked at, with a large clear pane (Principled Transmission 1, Thin Wall, IOR 1.5, Base
Color c0) level between them; the camera stands under the pane. Direct light only (a still's direct pass, and an
animation frame's ReSTIR, whose shading takes the shadow ray's colour there) and no jitter, so the pane
scales the light the centre pixel gets by its slab's transmittance at normal incidence, written out here from
Fresnel and the summed internal reflections: r = ((IOR - 1) / (IOR + 1))^2, T = c0 (1 - r)^2 / (1 - (r c0)^2).
With shadow rays stopped at the pane (the build without HAS_THIN_SHADOW) the pixel is black."""

from __future__ import annotations

import numpy as np
import pytest
import restircl.upload.device_scene as device_scene
from restircl import Camera, Light, Material, Mesh, Renderer, Scene, Settings, look_at, translation
from restircl.scenes.shapes import quad

C0 = np.array([0.9, 0.75, 0.5])
SIZE = 17


def centre(pane: bool, method: str = "reference") -> np.ndarray:
    fv, ft = quad(8.0, 8.0)
    mats = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"),
            Material("pane", tuple(C0), roughness=0.0, ior=1.5, specular=0.5, transmission=1.0, distribution="ggx",
                     thin_wall=True)]
    meshes = [Mesh("floor", fv, ft, 0)]
    if pane:
        meshes.append(Mesh("pane", fv * 0.5, ft, 1, translation(0.0, 0.0, 1.0)))
    cam = Camera(look_at((0.0, -0.6, 0.5), (0.0, 0.0, 0.0))[None], SIZE, SIZE, lens=50.0)
    scene = Scene(meshes, mats, [Light("bulb", "point", (1.0, 1.0, 1.0), 100.0, translation(0.0, 0.0, 2.0))], cam,
                  name="thin_wall_shadow")
    r = Renderer(scene, Settings(method=method, max_bounces=0, jitter=False, taa=False))
    img = (r.render_still(0, 1) if method == "reference" else r.render_frame(0)).color
    return img[SIZE // 2, SIZE // 2, :3].astype(np.float64)


@pytest.mark.parametrize("method", ["reference", "restir"])  # a still's direct pass; an animation frame's ReSTIR
def test_a_clear_pane_passes_its_transmittance(device, method):
    r = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2
    expected = C0 * (1 - r) ** 2 / (1 - (r * C0) ** 2)
    ratio = centre(True, method) / centre(False, method)
    assert np.allclose(ratio, expected, rtol=2e-3), (ratio, expected)


def test_stopped_shadow_rays_leave_it_black(device, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(device_scene, "scene_has_thin_shadow", lambda scene: False)
    assert np.all(centre(True) == 0.0)
