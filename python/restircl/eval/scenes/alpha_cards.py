"""The alpha scene of the transparency tests and measurements (issue 39): leaf cards cut out by an image's alpha
and a half-transparent pane, over a floor lit by an area light, so that the camera sees the floor through both and
their shadows (transparent shadows) fall on it; and a stack of cards for the stress suite and the bound on
transparent bounces.

The leaf image is made here (a lobed leaf shape, alpha 1 inside, 0 outside, soft at a one-texel rim), so the scenes
need no file. Units as everywhere: metres, Watts (docs/units.md).
"""

from __future__ import annotations

import numpy as np

from ...environment.world import Environment
from ...materials.material import Material
from ...materials.textures import ImageTexture
from ...scene.camera import Camera
from ...scene.light import Light
from ...scene.mesh import Mesh
from ...scene.scene import Scene
from ...scene.transforms import look_at, translation

QUAD_UV = np.array([[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[0.0, 0.0], [1.0, 1.0], [0.0, 1.0]]])


def leaf_image(size: int = 32) -> np.ndarray:
    """(size, size, 4) uint8 RGBA, top row first: a green leaf (alpha 255) on transparent black (alpha 0)."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size * 2.0 - 1.0
    r = np.hypot(x, y)
    angle = np.arctan2(y, x)
    inside = r < 0.55 + 0.3 * np.abs(np.cos(2.5 * angle))  # five lobes
    img = np.zeros((size, size, 4), np.uint8)
    img[..., 0], img[..., 1], img[..., 2] = 40, 150, 30
    img[..., 3] = np.where(inside, 255, 0)
    return img


def card(name: str, corner, ex, ey, material: int) -> Mesh:
    """A quad corner, corner + ex, corner + ex + ey, corner + ey with the UV square on it."""
    c, a, b = (np.asarray(v, dtype=np.float64) for v in (corner, ex, ey))
    return Mesh(name, np.array([c, c + a, c + a + b, c + b]), np.array([[0, 1, 2], [0, 2, 3]]), material,
                uvs=QUAD_UV.copy())


def leaf_material(image: np.ndarray | None = None) -> Material:
    """A Principled BSDF (no specular) of the leaf's green, its Alpha the image's alpha (Linear, the node's
    default)."""
    img = leaf_image() if image is None else image
    return Material("leaf", albedo=(0.16, 0.6, 0.12), alpha=ImageTexture(img, name="leaf", alpha=True))


def alpha_cards(width: int = 48, height: int = 36, pane_alpha: float = 0.5, world: bool = False) -> Scene:
    """A 4 x 4 m white floor, a 2 x 2 m area light 2.5 m above it, three leaf cards (alpha-masked, 0.6 m) and a
    1.2 x 0.8 m pane of coverage `pane_alpha` (a reddish diffuse) between them, 0.6-1.0 m above the floor; the camera
    looks down at 40 degrees. `world`: a dim grey world too (film transparency shows it as alpha)."""
    materials = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"), leaf_material(),
                 Material("pane", (0.8, 0.3, 0.2), kind="diffuse", alpha=pane_alpha)]
    meshes = [card("floor", (-2, -2, 0), (4, 0, 0), (0, 4, 0), 0),
              card("leaf_a", (-0.9, -0.6, 0.8), (0.6, 0, 0), (0, 0.6, 0.1), 1),
              card("leaf_b", (-0.5, -0.2, 0.6), (0.6, 0.1, 0), (0, 0.6, 0), 1),
              card("leaf_c", (-1.1, 0.2, 0.9), (0.6, 0, 0.1), (0, 0.6, 0), 1),
              card("pane", (0.2, -0.6, 1.0), (1.2, 0, 0), (0, 0.8, 0), 2)]
    light = Light("panel", "area", (1.0, 1.0, 1.0), 400.0, translation(0.0, 0.0, 2.5), shape="SQUARE", size=2.0)
    cam = Camera(look_at((0.0, -3.2, 3.0), (0.0, 0.0, 0.5)), width, height, lens=30.0)
    env = Environment(color=(0.05, 0.05, 0.05), strength=1.0) if world else None
    return Scene(meshes, materials, [light], cam, name="alpha_cards", environment=env)


def card_stack(count: int = 1000, alpha: float = 0.5, width: int = 16, height: int = 12, spacing: float = 1e-3,
               floor: bool = True) -> Scene:
    """`count` horizontal cards of coverage `alpha` stacked `spacing` apart over a white floor under an area light,
    seen from above: every camera and shadow ray meets all of them."""
    materials = [Material("floor", (0.8, 0.8, 0.8), kind="diffuse"),
                 Material("card", (0.2, 0.6, 0.2), kind="diffuse", alpha=alpha)]
    meshes = [card("floor", (-2, -2, 0), (4, 0, 0), (0, 4, 0), 0)] if floor else []
    verts, tris = [], []
    for k in range(count):
        z = 0.5 + k * spacing
        verts.append([[-1, -1, z], [1, -1, z], [1, 1, z], [-1, 1, z]])
        tris.append(np.array([[0, 1, 2], [0, 2, 3]]) + 4 * k)
    meshes.append(Mesh("cards", np.concatenate(verts).astype(np.float64), np.concatenate(tris), 1,
                       uvs=np.tile(QUAD_UV, (count, 1, 1))))
    light = Light("panel", "area", (1.0, 1.0, 1.0), 200.0, translation(0.0, 0.0, 0.5 + count * spacing + 1.0),
                  shape="SQUARE", size=1.0)
    cam = Camera(look_at((0.0, -0.3, 0.5 + count * spacing + 3.0), (0.0, 0.0, 0.0)), width, height, lens=35.0)
    return Scene(meshes, materials, [light], cam, name="card_stack")
