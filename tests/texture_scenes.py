"""Small scenes for the texture tests: a UV-mapped square facing a camera that sees exactly the square."""

from __future__ import annotations

import math

import numpy as np
from restircl import Camera, Light, Material, Mesh, Scene, look_at

SQUARE_UVS = np.array([[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]], float)


def square_mesh(half: float = 1.0, **kw) -> Mesh:
    v = np.array([[-half, -half, 0], [half, -half, 0], [half, half, 0], [-half, half, 0]], float)
    return Mesh("square", v, np.array([[0, 1, 2], [0, 2, 3]]), 0, uvs=SQUARE_UVS.copy(), **kw)


def facing_square(material: Material, size: int = 32, distance: float = 4.0, half: float = 1.0) -> Scene:
    """A square of side 2 half at z = 0 facing +Z, filling a size x size view from `distance` on the +Z axis
    (pixel (x, y) centre sees u = (x + 0.5) / size, v = 1 - (y + 0.5) / size); a sun from the camera's side."""
    cam = Camera(look_at((0, 0, distance), (0, 0, 0), (0, 1, 0)), size, size)
    cam.set_fov(2 * math.atan(half / distance))
    sun = Light("sun", "sun", (1, 1, 1), 1.0, look_at((0, 0, 1), (0, 0, 0), (0, 1, 0)))
    return Scene([square_mesh(half)], [material], [sun], cam)


def pixel_uv(size: int) -> tuple[np.ndarray, np.ndarray]:
    """(u, v) seen by each pixel centre of facing_square, (size, size) arrays, row 0 at the top."""
    c = (np.arange(size) + 0.5) / size
    return np.broadcast_to(c[None, :], (size, size)), np.broadcast_to(1.0 - c[:, None], (size, size))
