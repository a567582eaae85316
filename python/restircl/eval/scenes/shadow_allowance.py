"""A scene for the transparent shadows' allowance (issue 39): the camera sees a floor through `front` vertical cards,
and the floor is lit by an area light through `over` horizontal cards stacked above it, all of coverage `alpha`.
The front cards cover the left half of the view. Cycles counts a shadow ray's transparent surfaces against
Transparent Max Bounces less those the camera ray passed: with bound T, the floor seen through the front cards is
lit through the stack only where front + over <= T, the floor on the right where over <= T.
"""

from __future__ import annotations

import numpy as np

from ...materials.material import Material
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation
from .alpha_cards import QUAD_UV


def _quads(name: str, corners: list[np.ndarray], ex: np.ndarray, ey: np.ndarray, material: int) -> Mesh:
    verts = np.concatenate([[c, c + ex, c + ex + ey, c + ey] for c in corners]).astype(np.float64)
    tris = np.concatenate([np.array([[0, 1, 2], [0, 2, 3]]) + 4 * k for k in range(len(corners))])
    return Mesh(name, verts, tris, material, uvs=np.tile(QUAD_UV, (len(corners), 1, 1)))


def front_and_over(front: int = 2, over: int = 3, alpha: float = 0.25, width: int = 32,
                   height: int = 24) -> Scene:
    """A white 4 x 4 m floor under a 1 m square area light 2.5 m up; `over` 3 x 3 m cards 5 cm apart from 1 m up;
    `front` 3 x 3 m upright cards 10 cm apart across the left half of the view of a camera 0.6 m up, looking at the
    floor from under the stack, so that its rays there meet every front card and none of the others, and the floor's
    shadow rays every card over it and none in front."""
    materials = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"),
                 Material("card", (0.2, 0.6, 0.2), kind="diffuse", alpha=alpha)]
    floor = _quads("floor", [np.array([-2.0, -2.0, 0.0])], np.array([4.0, 0, 0]), np.array([0, 4.0, 0]), 0)
    meshes = [floor]
    if over:
        meshes.append(_quads("over", [np.array([-1.5, -1.5, 1.0 + 0.05 * k]) for k in range(over)],
                             np.array([3.0, 0, 0]), np.array([0, 3.0, 0]), 1))
    if front:
        meshes.append(_quads("front", [np.array([-3.0, -2.6 + 0.1 * k, -0.5]) for k in range(front)],
                             np.array([3.0, 0, 0]), np.array([0, 0, 3.0]), 1))
    light = Light("panel", "area", (1.0, 1.0, 1.0), 300.0, translation(0.0, 0.0, 2.5), shape="SQUARE", size=1.0)
    cam = Camera(look_at((0.0, -3.0, 0.6), (0.0, 0.0, 0.0)), width, height, lens=30.0)
    return Scene(meshes, materials, [light], cam, name="front_and_over")
