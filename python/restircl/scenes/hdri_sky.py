"""The built-in `sky` scene: a generated HDRI (a blue sky graded to a bright horizon over a dark ground, and a small
sun disk of about 1e3 times the sky's radiance) lighting a floor, a box and three spheres (one glossy), with no
other light. `sky_map` is the HDRI alone, for tests and for the Cycles comparison."""

from __future__ import annotations

import math

import numpy as np

from ..environment.world import Environment
from ..materials.material import Material
from ..scene.camera import Camera
from ..scene.mesh import Mesh
from ..scene.scene import Scene
from ..scene.transforms import look_at, translation
from .shapes import box, icosphere, quad

SUN_ELEVATION = math.radians(35.0)
SUN_AZIMUTH = math.radians(-60.0)  # atan2(y, x) of the direction towards the sun
SUN_RADIUS = math.radians(1.6)  # angular radius of the disk
SUN_RADIANCE = (2000.0, 1900.0, 1700.0)


def sun_direction() -> np.ndarray:
    ce = math.cos(SUN_ELEVATION)
    return np.array([ce * math.cos(SUN_AZIMUTH), ce * math.sin(SUN_AZIMUTH), math.sin(SUN_ELEVATION)])


def texel_directions(height: int, width: int) -> np.ndarray:
    """(H, W, 3) unit directions of the texel centres of an equirectangular map (Blender's mapping, row 0 up:
    opencl/lights/environment.h)."""
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    theta = np.pi * v[:, None]
    phi = np.pi * (1.0 - 2.0 * u[None, :])
    st = np.sin(theta)
    return np.stack(np.broadcast_arrays(st * np.cos(phi), st * np.sin(phi), np.cos(theta)), axis=-1)


def sky_map(height: int = 256, width: int = 512, sun_scale: float = 1.0, sun: np.ndarray | None = None
            ) -> np.ndarray:
    """(H, W, 3) float32 linear radiance: sky, ground and sun disk (the sun's radiance times `sun_scale`, towards
    `sun`, default sun_direction())."""
    d = texel_directions(height, width)
    z = d[..., 2:3]
    zenith, horizon, ground = np.array([0.08, 0.18, 0.5]), np.array([0.6, 0.7, 0.85]), np.array([0.12, 0.1, 0.08])
    t = np.clip(z, 0.0, 1.0) ** 0.4
    sky = horizon * (1.0 - t) + zenith * t
    rgb = np.where(z >= 0.0, sky, ground * np.clip(1.0 + 2.0 * z, 0.3, 1.0))
    cos_sun = d @ (sun_direction() if sun is None else np.asarray(sun, np.float64) / np.linalg.norm(sun))
    rgb = np.where(cos_sun[..., None] >= math.cos(SUN_RADIUS), np.array(SUN_RADIANCE) * sun_scale, rgb)
    return rgb.astype(np.float32)


def sky(width: int = 320, height: int = 180, frames: int = 1, map_height: int = 256) -> Scene:

    fv, ft = quad(12, 12)
    bv, bt = box((1.0, 1.0, 1.0))
    sv, st = icosphere(3, 0.5)
    materials = [Material("floor", (0.5, 0.5, 0.5)), Material("clay", (0.7, 0.45, 0.3)),
                 Material("white", (0.8, 0.8, 0.8)),
                 Material("gloss", (0.8, 0.8, 0.8), metallic=1.0, roughness=0.25)]
    meshes = [Mesh("floor", fv, ft, 0), Mesh("box", bv, bt, 1, translation(-1.2, 0.4, 0.5)),
              Mesh("ball", sv, st, 2, translation(0.3, -0.4, 0.5)),
              Mesh("gloss_ball", sv, st, 3, translation(1.5, 0.5, 0.5))]
    world = Environment("sky", color=(1.0, 1.0, 1.0), image=sky_map(map_height, 2 * map_height))
    eye = look_at((0.5, -6.0, 2.2), (0.2, 0.0, 0.6))
    cam = Camera(np.repeat(eye[None], max(frames, 1), axis=0), width, height, lens=35.0)
    return Scene(meshes, materials, [], cam, name="sky", environment=world)
