"""Glass under a moving camera (issue 39, docs/design.md "Glass under motion"): a smooth glass sphere in front of a
diffuse wall with a bright emissive stripe and a red box, lit by a point light, seen from a camera orbiting the
sphere. What the sphere shows (the stripe and the box, refracted and upside down) moves with the view, not with
the sphere's surface, which is what TAA's motion vectors follow: the case for ghosting through glass
(tests/render/test_taa_glass.py, tools/experiments/taa_glass_ghost.py)."""

from __future__ import annotations

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from ...scenes.shapes import box, icosphere, quad
from .glass import glass_material

GLASS_MESH = 4  # the sphere's index in the scene's meshes


def glass_orbit(width: int = 40, height: int = 24, frames: int = 12, deg_per_frame: float = 3.0,
                glass: bool = True, roughness: float = 0.0) -> Scene:
    """The camera orbits the sphere deg_per_frame a frame at 3 m; glass=False leaves the sphere out (its pixels:
    where the depth differs); `roughness` makes it rough glass."""
    fv, ft = quad(8, 8)
    wv, wt = quad(6, 3)
    rot_x = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], float)
    sv, st = quad(0.25, 1.2)
    bv, bt = box((0.4, 0.4, 0.6))
    gv, gt = icosphere(3, 0.45)
    materials = [Material("floor", (0.6, 0.6, 0.6)), Material("wall", (0.6, 0.5, 0.4)),
                 Material("stripe", (0, 0, 0), (1.0, 0.9, 0.8), 20.0), Material("red", (0.8, 0.1, 0.1)),
                 glass_material("glass", roughness)]
    meshes = [Mesh("floor", fv, ft, 0), Mesh("wall", wv @ rot_x.T + (0, 1.5, 1.5), wt, 1),
              Mesh("stripe", sv @ rot_x.T + (0.2, 1.45, 0.9), st, 2), Mesh("red", bv + (-0.4, 0.9, 0.3), bt, 3),
              Mesh("glass", gv, gt, 4, translation(0.0, 0.0, 0.6))]
    if not glass:
        meshes = meshes[:GLASS_MESH]
    lights = [Light("fill", "point", (1, 1, 1), 300.0, translation(-1.0, -1.5, 2.5), radius=0.2)]
    eyes = []
    for f in range(frames):
        a = np.radians(-15.0 + deg_per_frame * f)
        eyes.append(look_at((3.0 * np.sin(a), -3.0 * np.cos(a), 1.0), (0.0, 0.5, 0.6)))
    return Scene(meshes, materials, lights, Camera(np.array(eyes), width, height, lens=35.0), name="glass_orbit")
