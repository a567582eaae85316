"""A light whose shadows are linked (an object excluded from its blockers) in the path pass (opencl/path/emitters.h,
path/mis.h): at a path vertex both NEE and the BSDF ray find it, weighted by MIS, the BSDF ray through what does not
shadow the light (the light's own blockers tested between the vertex and the light, as NEE's shadow ray tests them).

The scene: a wall that the light does not light (receivers EXCLUDE wall), so its pixels hold only light bounced off
the floor; a black shade between the light and the floor that does not shadow it (blockers EXCLUDE shade), so a
floor vertex's BSDF ray towards the light stops at the shade; a glossy metal floor and a sphere light close over it,
so that BSDF rays carry a good part of its light (where the floor mirrors it towards the wall). Reference: the same
render with NEE alone finding the light (the estimator of before, TEST_PATH_LINKED_NEE_ONLY). Negative control: NEE
with MIS weight 1 beside the BSDF rays' weights (TEST_PATH_LINKED_NEE_WEIGHT_ONE): the light counted more than once.
Measured when written (6 x 48 frames): both ways 0.2043, NEE alone 0.2066 (difference 0.3 standard errors; batch sd
0.011 against 0.015), the control 0.2911 (+41 %, 9 standard errors)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Light, Material, Mesh, Renderer, Scene, Settings, look_at, translation
from restircl.scene.camera import Camera
from restircl.scene.linking import Linking

from ..bias_controls import built_with
from ..lights.linking_scene import quad

BATCHES, FRAMES = 6, 48


def shaded_scene() -> Scene:
    floor = quad("floor", -3.0, 3.0, -3.0, 3.0, 0.0, material=2)
    wall = Mesh("wall", vertices=[(-3.0, 2.0, 0.0), (3.0, 2.0, 0.0), (3.0, 2.0, 3.0), (-3.0, 2.0, 3.0)],
                triangles=[(0, 1, 2), (0, 2, 3)], material_ids=0)
    shade = quad("shade", -0.6, 0.6, -0.1, 1.1, 0.7, material=1)
    light = Light("bulb", "point", power=300.0, transforms=translation(0.0, 0.5, 1.3), radius=0.35)
    light.linking = Linking(receivers={"wall": "EXCLUDE"}, blockers={"shade": "EXCLUDE"})
    cam = Camera(transforms=look_at((0.0, -3.0, 1.6), (0.0, 2.0, 1.2)), width=24, height=18)
    cam.set_fov(math.radians(40))
    mats = [Material(name="grey", albedo=(0.7, 0.7, 0.7)), Material(name="black", albedo=(0.0, 0.0, 0.0)),
            Material(name="metal", albedo=(0.8, 0.8, 0.8), metallic=1.0, roughness=0.25)]
    return Scene(meshes=[floor, wall, shade], materials=mats, lights=[light], camera=cam)


def batch_means() -> np.ndarray:
    """The image mean of BATCHES independent stills (RIS with BSDF candidates, whose lights the path's BSDF rays
    look for too; 2 bounces)."""
    scene = shaded_scene()
    return np.array([Renderer(scene, Settings(method="ris", bsdf_sampling="on", seed=41 + b, max_bounces=2,
                                                diffuse_bounces=2))
                     .render_still(0, samples=FRAMES).color[..., :3].mean() for b in range(BATCHES)])


@pytest.fixture(scope="module")
def found_by_both(device):
    return batch_means()


@pytest.fixture(scope="module")
def nee_alone(device):
    with pytest.MonkeyPatch.context() as mp:
        built_with(mp, "TEST_PATH_LINKED_NEE_ONLY")
        return batch_means()


def differ(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """The difference of the means and its standard error."""
    return float(a.mean() - b.mean()), math.hypot(a.std(ddof=1), b.std(ddof=1)) / math.sqrt(BATCHES)


def test_linked_light_found_by_both_ways_matches_nee_alone(found_by_both, nee_alone):
    d, se = differ(found_by_both, nee_alone)
    assert nee_alone.mean() > 0.05
    assert abs(d) < 4 * se + 2e-3 * nee_alone.mean(), (d, se, nee_alone.mean())


def test_the_check_sees_the_light_counted_twice(nee_alone, device):
    with pytest.MonkeyPatch.context() as mp:
        built_with(mp, "TEST_PATH_LINKED_NEE_WEIGHT_ONE")
        twice = batch_means()
    d, se = differ(twice, nee_alone)
    assert d > 4 * se + 2e-3 * nee_alone.mean(), (d, se, nee_alone.mean())
